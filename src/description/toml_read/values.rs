//! Reading spanned TOML values: numbers, vectors, colours and tables, each failure located at
//! the value's span, unknown keys answered with the nearest valid one.

use crate::description::source::{Diagnostic, did_you_mean, nearest};
use crate::error::{Error, Result};
use crate::math::{Rgb, Vec3};
use std::ops::Range;
use std::path::{Path, PathBuf};
use toml::Spanned;
use toml::de::{DeTable, DeValue};

pub(super) struct Cx<'a> {
    pub path: &'a Path,
    pub text: &'a str,
    pub base_dir: &'a Path,
}

pub(super) type Value<'i> = Spanned<DeValue<'i>>;

impl<'a> Cx<'a> {
    pub(super) fn err(&self, span: Range<usize>, message: impl Into<String>) -> Error {
        Error::SceneFile(Box::new(Diagnostic::at_span(
            self.path, self.text, span, message,
        )))
    }

    pub(super) fn table<'t, 'i>(&'t self, v: &'t Value<'i>, what: &str) -> Result<Table<'t, 'i>> {
        match v.get_ref() {
            DeValue::Table(map) => Ok(Table::new(self, map, v.span(), what)),
            other => Err(self.err(
                v.span(),
                format!("{what} must be a table, found {}", kind(other)),
            )),
        }
    }

    /// A file named in the scene, resolved and checked to exist.
    pub(super) fn file(&self, v: &Value, what: &str) -> Result<PathBuf> {
        let name = str_of(self, v, what)?;
        let resolved = self.base_dir.join(name);
        if !resolved.is_file() {
            return Err(self.err(
                v.span(),
                format!(
                    "{what} '{name}' not found (looked for {})",
                    std::path::absolute(&resolved)
                        .unwrap_or(resolved.clone())
                        .display()
                ),
            ));
        }
        Ok(PathBuf::from(name))
    }
}

pub(super) fn kind(v: &DeValue) -> &'static str {
    match v {
        DeValue::String(_) => "a string",
        DeValue::Integer(_) => "an integer",
        DeValue::Float(_) => "a float",
        DeValue::Boolean(_) => "a boolean",
        DeValue::Datetime(_) => "a date-time",
        DeValue::Array(_) => "an array",
        DeValue::Table(_) => "a table",
    }
}

pub(super) fn str_of<'v>(cx: &Cx, v: &'v Value, what: &str) -> Result<&'v str> {
    match v.get_ref() {
        DeValue::String(s) => Ok(s.as_ref()),
        other => Err(cx.err(
            v.span(),
            format!("{what} must be a string, found {}", kind(other)),
        )),
    }
}

pub(super) fn number(cx: &Cx, v: &Value, what: &str) -> Result<f64> {
    let x = match v.get_ref() {
        DeValue::Integer(i) => i64::from_str_radix(i.as_str(), i.radix())
            .ok()
            .map(|i| i as f64),
        DeValue::Float(f) => f.as_str().parse::<f64>().ok(),
        other => {
            return Err(cx.err(
                v.span(),
                format!("{what} must be a number, found {}", kind(other)),
            ));
        }
    };
    match x {
        Some(x) if x.is_finite() => Ok(x),
        _ => Err(cx.err(v.span(), format!("{what} must be a finite number"))),
    }
}

/// A number read directly as `f32`, so that a value written from an `f32` reads back exactly.
pub(super) fn float(cx: &Cx, v: &Value, what: &str) -> Result<f32> {
    let x = match v.get_ref() {
        DeValue::Float(f) => f.as_str().parse::<f32>().ok(),
        _ => Some(number(cx, v, what)? as f32),
    };
    match x {
        Some(x) if x.is_finite() => Ok(x),
        _ => Err(cx.err(v.span(), format!("{what} must be a finite number"))),
    }
}

pub(super) fn integer(cx: &Cx, v: &Value, what: &str, max: u64) -> Result<u64> {
    let parsed = match v.get_ref() {
        DeValue::Integer(i) => i64::from_str_radix(i.as_str(), i.radix()).ok(),
        other => {
            return Err(cx.err(
                v.span(),
                format!("{what} must be a whole number, found {}", kind(other)),
            ));
        }
    };
    match parsed {
        Some(i) if i >= 0 && i as u64 <= max => Ok(i as u64),
        _ => Err(cx.err(
            v.span(),
            format!("{what} must be a whole number from 0 to {max}"),
        )),
    }
}

pub(super) fn array<'v, 'i>(cx: &Cx, v: &'v Value<'i>, what: &str) -> Result<&'v [Value<'i>]> {
    match v.get_ref() {
        DeValue::Array(a) => Ok(a.as_ref()),
        other => Err(cx.err(
            v.span(),
            format!("{what} must be an array, found {}", kind(other)),
        )),
    }
}

pub(super) fn floats<const N: usize>(cx: &Cx, v: &Value, what: &str) -> Result<[f32; N]> {
    let items = array(cx, v, what)
        .map_err(|_| cx.err(v.span(), format!("{what} must be an array of {N} numbers")))?;
    if items.len() != N {
        return Err(cx.err(
            v.span(),
            format!("{what} must have {N} numbers, found {}", items.len()),
        ));
    }
    let mut out = [0.0; N];
    for (o, item) in out.iter_mut().zip(items) {
        *o = float(cx, item, what)?;
    }
    Ok(out)
}

pub(super) fn vec3(cx: &Cx, v: &Value, what: &str) -> Result<Vec3> {
    Ok(Vec3::from_array(floats::<3>(cx, v, what)?))
}

/// A colour: `[r, g, b]`, or one number for grey. Components must not be negative.
pub(super) fn color(cx: &Cx, v: &Value, what: &str) -> Result<Rgb> {
    let c = match v.get_ref() {
        DeValue::Array(_) => Vec3::from_array(floats::<3>(cx, v, what)?),
        DeValue::Integer(_) | DeValue::Float(_) => Vec3::splat(float(cx, v, what)?),
        other => {
            return Err(cx.err(
                v.span(),
                format!(
                    "{what} must be a colour [r, g, b] or a number, found {}",
                    kind(other)
                ),
            ));
        }
    };
    if c.min_element() < 0.0 {
        return Err(cx.err(v.span(), format!("{what} must not be negative")));
    }
    Ok(c)
}

/// A table being read: knows its keys, location and what to call itself in messages.
pub(super) struct Table<'t, 'i> {
    pub cx: &'t Cx<'t>,
    pub map: &'t DeTable<'i>,
    pub span: Range<usize>,
    pub what: String,
}

impl<'t, 'i> Table<'t, 'i> {
    pub(super) fn new(
        cx: &'t Cx<'t>,
        map: &'t DeTable<'i>,
        span: Range<usize>,
        what: &str,
    ) -> Self {
        Self {
            cx,
            map,
            span,
            what: what.to_owned(),
        }
    }

    /// Refuse keys outside `allowed`, suggesting the nearest one.
    pub(super) fn allow(&self, allowed: &[&str]) -> Result<()> {
        for key in self.map.keys() {
            let k = key.get_ref().as_ref();
            if !allowed.contains(&k) {
                let hint = did_you_mean(k, allowed);
                return Err(self.cx.err(
                    key.span(),
                    format!(
                        "unknown key '{k}' in {}{hint} (expected one of: {})",
                        self.what,
                        allowed.join(", ")
                    ),
                ));
            }
        }
        Ok(())
    }

    pub(super) fn get(&self, key: &str) -> Option<&'t Value<'i>> {
        self.map.get(key)
    }

    pub(super) fn label(&self, key: &str) -> String {
        format!("'{key}' in {}", self.what)
    }

    pub(super) fn required(&self, key: &str) -> Result<&'t Value<'i>> {
        self.get(key).ok_or_else(|| {
            // Point at the table's first line: its header or opening brace.
            let start = self.span.start;
            self.cx
                .err(start..start + 1, format!("{} needs '{key}'", self.what))
        })
    }

    pub(super) fn opt_str(&self, key: &str) -> Result<Option<&'t str>> {
        self.get(key)
            .map(|v| str_of(self.cx, v, &self.label(key)))
            .transpose()
    }

    pub(super) fn req_str(&self, key: &str) -> Result<&'t str> {
        str_of(self.cx, self.required(key)?, &self.label(key))
    }

    pub(super) fn opt_f32(&self, key: &str) -> Result<Option<f32>> {
        self.get(key)
            .map(|v| float(self.cx, v, &self.label(key)))
            .transpose()
    }

    pub(super) fn positive(&self, key: &str) -> Result<f32> {
        let v = self.required(key)?;
        let x = float(self.cx, v, &self.label(key))?;
        if x <= 0.0 {
            return Err(self
                .cx
                .err(v.span(), format!("{} must be positive", self.label(key))));
        }
        Ok(x)
    }

    pub(super) fn opt_int(&self, key: &str, max: u64) -> Result<Option<u64>> {
        self.get(key)
            .map(|v| integer(self.cx, v, &self.label(key), max))
            .transpose()
    }

    pub(super) fn opt_bool(&self, key: &str) -> Result<Option<bool>> {
        self.get(key)
            .map(|v| match v.get_ref() {
                DeValue::Boolean(b) => Ok(*b),
                other => Err(self.cx.err(
                    v.span(),
                    format!(
                        "{} must be true or false, found {}",
                        self.label(key),
                        kind(other)
                    ),
                )),
            })
            .transpose()
    }

    pub(super) fn req_vec3(&self, key: &str) -> Result<Vec3> {
        vec3(self.cx, self.required(key)?, &self.label(key))
    }

    pub(super) fn opt_vec3(&self, key: &str) -> Result<Option<Vec3>> {
        self.get(key)
            .map(|v| vec3(self.cx, v, &self.label(key)))
            .transpose()
    }

    pub(super) fn opt_color(&self, key: &str) -> Result<Option<Rgb>> {
        self.get(key)
            .map(|v| color(self.cx, v, &self.label(key)))
            .transpose()
    }

    /// `[[key]]` entries (or an inline array of tables); none if the key is absent.
    pub(super) fn array_of_tables(&self, key: &str) -> Result<Vec<&'t Value<'i>>> {
        match self.get(key) {
            None => Ok(Vec::new()),
            Some(v) => Ok(
                array(self.cx, v, &format!("'{key}' (write [[{key}]] tables)"))?
                    .iter()
                    .collect(),
            ),
        }
    }

    /// A material name that must be defined in `[materials]`.
    pub(super) fn material_ref(&self, key: &str, names: &[&str]) -> Result<Option<String>> {
        self.name_ref(key, names, "material", "[materials]")
    }

    /// A name at `key` that must be one of `names`, the things of `kind` the file defines in
    /// its `table`.
    pub(super) fn name_ref(
        &self,
        key: &str,
        names: &[&str],
        kind: &str,
        table: &str,
    ) -> Result<Option<String>> {
        let Some(v) = self.get(key) else {
            return Ok(None);
        };
        let name = str_of(self.cx, v, &self.label(key))?;
        if !names.contains(&name) {
            let hint = match nearest(name, names) {
                Some(n) => format!("; did you mean '{n}'?"),
                None if names.is_empty() => format!("; the file defines no {table}"),
                None => format!(" (defined: {})", names.join(", ")),
            };
            return Err(self.cx.err(
                v.span(),
                format!("{kind} '{name}' is not defined in {table}{hint}"),
            ));
        }
        Ok(Some(name.to_owned()))
    }
}
