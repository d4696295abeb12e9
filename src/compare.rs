//! Image error metrics used to validate renders against references.
//!
//! relMSE = mean over pixels of (a − b)² / (b² + 0.01), the measure the Cornell box
//! reference's peer renderers (Mitsuba 3, pbrt-v4, POV-Ray) were compared by.

use crate::film::Image;

/// Error of one channel (or all channels together).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ChannelError {
    pub rmse: f64,
    pub rel_mse: f64,
    /// mean(a) / mean(b).
    pub mean_ratio: f64,
}

#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Comparison {
    pub width: u32,
    pub height: u32,
    pub red: ChannelError,
    pub green: ChannelError,
    pub blue: ChannelError,
    pub overall: ChannelError,
}

/// A rectangle of pixels: rows `y0..y1`, columns `x0..x1` (end exclusive).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Crop {
    pub x0: u32,
    pub x1: u32,
    pub y0: u32,
    pub y1: u32,
}

/// The caustic region of the Cornell validation scene at 512×512: rows 326–343, columns 290–389.
pub const CORNELL_CAUSTIC_CROP: Crop = Crop {
    x0: 290,
    x1: 390,
    y0: 326,
    y1: 344,
};

#[derive(Default, Clone, Copy)]
struct Acc {
    se: f64,
    rel: f64,
    sum_a: f64,
    sum_b: f64,
    n: f64,
}

impl Acc {
    fn add(&mut self, a: f64, b: f64) {
        let d = a - b;
        self.se += d * d;
        self.rel += d * d / (b * b + 0.01);
        self.sum_a += a;
        self.sum_b += b;
        self.n += 1.0;
    }

    fn finish(&self) -> ChannelError {
        let n = self.n.max(1.0);
        ChannelError {
            rmse: (self.se / n).sqrt(),
            rel_mse: self.rel / n,
            mean_ratio: if self.sum_b == 0.0 {
                if self.sum_a == 0.0 {
                    1.0
                } else {
                    f64::INFINITY
                }
            } else {
                self.sum_a / self.sum_b
            },
        }
    }
}

/// Compare `a` against the reference `b` over `crop` (the whole image if `None`).
/// `None` if the sizes differ or the crop lies outside the image.
pub fn compare(a: &Image, b: &Image, crop: Option<Crop>) -> Option<Comparison> {
    if a.width != b.width || a.height != b.height {
        return None;
    }
    let c = crop.unwrap_or(Crop {
        x0: 0,
        x1: a.width,
        y0: 0,
        y1: a.height,
    });
    if c.x0 >= c.x1 || c.y0 >= c.y1 || c.x1 > a.width || c.y1 > a.height {
        return None;
    }
    let mut ch = [Acc::default(); 3];
    let mut all = Acc::default();
    for y in c.y0..c.y1 {
        for x in c.x0..c.x1 {
            let (pa, pb) = (a.get(x, y).to_array(), b.get(x, y).to_array());
            for k in 0..3 {
                let (va, vb) = (f64::from(pa[k]), f64::from(pb[k]));
                ch[k].add(va, vb);
                all.add(va, vb);
            }
        }
    }
    Some(Comparison {
        width: c.x1 - c.x0,
        height: c.y1 - c.y0,
        red: ch[0].finish(),
        green: ch[1].finish(),
        blue: ch[2].finish(),
        overall: all.finish(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Rgb;

    #[test]
    fn identical_images_have_zero_error_and_unit_ratio() {
        let mut a = Image::new(4, 3);
        a.set(1, 1, Rgb::new(1.0, 2.0, 3.0));
        let c = compare(&a, &a, None).expect("same size");
        assert_eq!(c.overall.rmse, 0.0);
        assert_eq!(c.overall.rel_mse, 0.0);
        assert_eq!(c.red.mean_ratio, 1.0);
    }

    #[test]
    fn known_difference_gives_known_numbers() {
        let mut a = Image::new(2, 1);
        let mut b = Image::new(2, 1);
        a.pixels = vec![Rgb::splat(1.1), Rgb::splat(1.0)];
        b.pixels = vec![Rgb::splat(1.0), Rgb::splat(1.0)];
        let c = compare(&a, &b, None).expect("same size");
        // One pixel off by 0.1: MSE 0.005, relMSE 0.005 / 1.01, ratio 2.1 / 2.
        assert!((c.overall.rmse - 0.005f64.sqrt()).abs() < 1e-6);
        assert!((c.overall.rel_mse - 0.005 / 1.01).abs() < 1e-6);
        assert!((c.green.mean_ratio - 1.05).abs() < 1e-6);
        assert!(compare(&a, &Image::new(3, 1), None).is_none());
        let crop = Crop {
            x0: 1,
            x1: 2,
            y0: 0,
            y1: 1,
        };
        assert_eq!(
            compare(&a, &b, Some(crop)).expect("in range").overall.rmse,
            0.0
        );
    }
}
