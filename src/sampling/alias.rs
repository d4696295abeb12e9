//! Walker's alias method (Walker 1977; Vose's construction, 1991; pbrt-v4 §A.1): a discrete
//! distribution sampled in constant time, whatever its number of items.
//!
//! Each of the `n` bins is chosen with probability 1/n and then keeps its own item with
//! probability `keep`, or gives its alias. Unlike inverting a CDF, the map from `u` to items is
//! not monotonic, so stratified `u` do not stay stratified; it serves where `u` is independent
//! per sample, as picking a triangle of an emitting mesh is.

use super::Weights;

/// One bin: the chance of keeping its own item, and the item it gives otherwise.
#[derive(Clone, Copy, Debug)]
struct Bin {
    keep: f64,
    alias: u32,
}

#[derive(Clone, Debug)]
pub struct AliasTable {
    bins: Vec<Bin>,
    weights: Weights,
}

impl AliasTable {
    /// Build from non-negative weights (negative ones count as zero). Returns `None` if there
    /// are none, they sum to zero, or there are more than `u32::MAX`.
    pub fn new(weights: &[f64]) -> Option<Self> {
        let weights = Weights::new(weights)?;
        let (values, total) = (&weights.values, weights.total);
        let n = values.len();
        u32::try_from(n).ok()?;
        // Each item's weight in units of a bin's share, 1/n of the total.
        let mut scaled: Vec<f64> = values.iter().map(|w| w / total * n as f64).collect();
        let (mut under, mut over): (Vec<u32>, Vec<u32>) =
            (0..n as u32).partition(|&i| scaled[i as usize] < 1.0);
        let mut bins: Vec<Bin> = (0..n as u32)
            .map(|i| Bin {
                keep: 1.0,
                alias: i,
            })
            .collect();
        while let (Some(&small), Some(&large)) = (under.last(), over.last()) {
            under.pop();
            bins[small as usize] = Bin {
                keep: scaled[small as usize],
                alias: large,
            };
            // The large item gives the small bin's missing share.
            scaled[large as usize] -= 1.0 - scaled[small as usize];
            if scaled[large as usize] < 1.0 {
                over.pop();
                under.push(large);
            }
        }
        // What is left on either list is 1 up to rounding and keeps its own bin (keep = 1),
        // except an item of zero weight, which gives its bin to any item that has weight.
        if let Some(heavy) = values.iter().position(|&w| w > 0.0) {
            for i in under {
                if values[i as usize] == 0.0 {
                    bins[i as usize] = Bin {
                        keep: 0.0,
                        alias: heavy as u32,
                    };
                }
            }
        }
        Some(Self { bins, weights })
    }

    /// The sum of the weights.
    pub fn total(&self) -> f64 {
        self.weights.total
    }

    /// Probability of item `i`.
    pub fn pmf(&self, i: usize) -> f32 {
        self.weights.pmf(i)
    }

    /// Pick an item with probability proportional to its weight; also returns `u` remapped to
    /// [0, 1) within the choice, so it can be reused.
    pub fn sample(&self, u: f32) -> (usize, f32) {
        let n = self.bins.len();
        let scaled = f64::from(u) * n as f64;
        let bin = (scaled as usize).min(n - 1);
        let within = scaled - bin as f64;
        let Bin { keep, alias } = self.bins[bin];
        let (item, rest) = if within < keep {
            (bin, within / keep)
        } else {
            (alias as usize, (within - keep) / (1.0 - keep))
        };
        (item, (rest as f32).clamp(0.0, 1.0 - f32::EPSILON))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The chance the table gives each item, summed over its bins exactly.
    fn chances(table: &AliasTable) -> Vec<f64> {
        let n = table.bins.len() as f64;
        let mut p = vec![0.0; table.bins.len()];
        for (i, bin) in table.bins.iter().enumerate() {
            p[i] += bin.keep / n;
            p[bin.alias as usize] += (1.0 - bin.keep) / n;
        }
        p
    }

    #[test]
    fn every_item_is_given_its_weights_share_and_zero_weights_never() {
        let layouts: [&[f64]; 5] = [
            &[1.0],
            &[0.0, 3.0, 0.0],
            &[1.0, 2.0, 3.0, 4.0, 0.0, 10.0],
            &[1e-12, 1.0, 1e12, 0.0, 5.0],
            &[0.1; 7],
        ];
        for weights in layouts {
            let table = AliasTable::new(weights).unwrap();
            let total: f64 = weights.iter().sum();
            for (i, (&w, p)) in weights.iter().zip(chances(&table)).enumerate() {
                assert!((p - w / total).abs() < 1e-12, "{weights:?} item {i}: {p}");
                if w == 0.0 {
                    assert_eq!(p, 0.0, "{weights:?} item {i}");
                }
            }
        }
        // Many random weights, some zero.
        let mut rng = crate::sampling::Rng::keyed(7, &[]);
        let weights: Vec<f64> = (0..1000)
            .map(|i| {
                if i % 7 == 0 {
                    0.0
                } else {
                    f64::from(rng.next_f32())
                }
            })
            .collect();
        let table = AliasTable::new(&weights).unwrap();
        let total: f64 = weights.iter().sum();
        for (&w, p) in weights.iter().zip(chances(&table)) {
            assert!((p - w / total).abs() < 1e-12);
            assert!(w > 0.0 || p == 0.0);
        }
    }

    #[test]
    fn sampling_follows_the_weights_and_remaps_u_uniformly() {
        let weights = [1.0, 0.0, 2.0, 5.0];
        let table = AliasTable::new(&weights).unwrap();
        let n = 200_000;
        let mut counts = [0usize; 4];
        let mut rest_below_half = [0usize; 4];
        for k in 0..n {
            let u = (k as f32 + 0.5) / n as f32;
            let (i, rest) = table.sample(u);
            counts[i] += 1;
            assert!((0.0..1.0).contains(&rest));
            if rest < 0.5 {
                rest_below_half[i] += 1;
            }
        }
        for i in 0..4 {
            let expected = weights[i] / 8.0;
            let seen = counts[i] as f64 / n as f64;
            assert!(
                (seen - expected).abs() < 1e-3,
                "item {i}: {seen} against {expected}"
            );
            if counts[i] > 0 {
                let half = rest_below_half[i] as f64 / counts[i] as f64;
                assert!(
                    (half - 0.5).abs() < 0.01,
                    "item {i}: remapped u below ½ {half}"
                );
            }
        }
    }

    #[test]
    fn no_weight_gives_no_table() {
        assert!(AliasTable::new(&[]).is_none());
        assert!(AliasTable::new(&[0.0, -1.0]).is_none());
        assert!(AliasTable::new(&[f64::INFINITY]).is_none());
    }
}
