//! Which of a recording's columns, records or WAV channels is which of the rig's four
//! accelerometers: `--channel KEY=SOURCE[*SCALE]`.
//!
//! KEY is one of disc_x, pad_x, pad_trail, pad_lead. SOURCE is a column's name (CSV: the header
//! cell as written, or its name without the unit, case-insensitive), a record's name (UFF:
//! any of its five ID lines, trimmed, case-insensitive), or `#N`: the N-th column after the
//! time column (CSV, counted from 1, the time column skipped), the N-th dataset-58 record
//! (UFF) or the N-th channel (WAV). SCALE multiplies the values as the file holds them into
//! m/s^2; with a SCALE the source's own unit (a header's `[g]`, a UFF record's units label) is
//! not used. A key left unmapped still matches a column or record named like it (`pad_x`,
//! `Pad X [g]`), as before.
//!
//! pad_x is the one channel an analysis needs; the others may be absent (see
//! `super::analysis`: without disc_x the estimator takes the band at constant speed).

use stickslip_model::rig::ACCEL_NAMES;

use crate::error::{HostError, Result};

/// Where a channel comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum ChannelSource {
    /// A column's or record's name (as given; matched case-insensitively).
    Name(String),
    /// The N-th column after time, record or WAV channel (from 1).
    Index(usize),
}

/// One `--channel KEY=SOURCE[*SCALE]`.
#[derive(Clone, Debug, PartialEq)]
pub struct ChannelSpec {
    /// 0 disc_x, 1 pad_x, 2 pad_trail, 3 pad_lead.
    pub key: usize,
    pub source: ChannelSource,
    /// Values x scale = m/s^2; `None`: the source's unit decides.
    pub scale: Option<f64>,
    /// The argument as given (for messages).
    pub arg: String,
}

impl ChannelSpec {
    /// The source as the user wrote it, for messages.
    pub fn source_text(&self) -> String {
        match &self.source {
            ChannelSource::Name(n) => format!("`{n}`"),
            ChannelSource::Index(i) => format!("#{i}"),
        }
    }
}

/// The `--channel` options of one command.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ChannelMap {
    pub specs: Vec<ChannelSpec>,
}

/// The rig's name of channel `key`.
pub fn key_name(key: usize) -> &'static str {
    ACCEL_NAMES[key]
}

/// Lower case, trimmed, quotes dropped: how names are compared.
pub fn fold(name: &str) -> String {
    name.trim().trim_matches('"').trim().to_lowercase()
}

impl ChannelMap {
    /// Parses the `--channel` arguments; errors name the option and the rule.
    pub fn parse(args: &[String]) -> Result<Self> {
        let mut specs: Vec<ChannelSpec> = Vec::new();
        for arg in args {
            let bad = |why: String| HostError::Input(format!("--channel {arg}: {why}"));
            let (key, rest) = arg
                .split_once('=')
                .ok_or_else(|| bad("expected KEY=SOURCE[*SCALE], e.g. pad_x=Acc1*9.80665 or pad_x=#2".into()))?;
            let k = fold(key).replace([' ', '-'], "_");
            let key = ACCEL_NAMES.iter().position(|n| *n == k).ok_or_else(|| {
                bad(format!("KEY `{}` is not a channel (the channels: {})", key.trim(), ACCEL_NAMES.join(", ")))
            })?;
            let (src, scale) = match rest.rsplit_once('*') {
                Some((s, f)) => {
                    let v: f64 = f.trim().parse().map_err(|_| bad(format!("SCALE `{}` is not a number", f.trim())))?;
                    if !(v.is_finite() && v != 0.0 && v.abs() <= 1e12) {
                        return Err(bad(format!("SCALE {v:.4e} must be finite, nonzero and at most 1e12 in size")));
                    }
                    (s, Some(v))
                }
                None => (rest, None),
            };
            let src = src.trim();
            let source = if let Some(n) = src.strip_prefix('#') {
                match n.trim().parse::<usize>() {
                    Ok(i) if i >= 1 => ChannelSource::Index(i),
                    _ => return Err(bad(format!("`{src}`: #N counts from 1 (the first column after time, record or channel)"))),
                }
            } else if src.is_empty() {
                return Err(bad("SOURCE is empty: a column's or record's name, or #N".into()));
            } else {
                ChannelSource::Name(src.to_string())
            };
            if let Some(prev) = specs.iter().find(|s| s.key == key) {
                return Err(bad(format!("{} is also mapped by --channel {}", ACCEL_NAMES[key], prev.arg)));
            }
            let same = |a: &ChannelSource, b: &ChannelSource| match (a, b) {
                (ChannelSource::Name(x), ChannelSource::Name(y)) => fold(x) == fold(y),
                _ => a == b,
            };
            if let Some(prev) = specs.iter().find(|s| same(&s.source, &source)) {
                return Err(bad(format!("{} is also mapped to {} by --channel {}", src, ACCEL_NAMES[prev.key], prev.arg)));
            }
            specs.push(ChannelSpec { key, source, scale, arg: arg.clone() });
        }
        Ok(ChannelMap { specs })
    }

    /// The mapping of channel `key`, if given.
    pub fn get(&self, key: usize) -> Option<&ChannelSpec> {
        self.specs.iter().find(|s| s.key == key)
    }

    pub fn is_empty(&self) -> bool {
        self.specs.is_empty()
    }

    /// Whether a name (a header cell's full text, its name part, or a record's ID line)
    /// matches `spec`'s source.
    pub fn matches_name(spec: &ChannelSpec, names: &[&str]) -> bool {
        match &spec.source {
            ChannelSource::Name(n) => {
                let want = fold(n);
                names.iter().any(|c| fold(c) == want)
            }
            ChannelSource::Index(_) => false,
        }
    }
}

/// "pad_x is needed" as one line for `label`, with what the file has.
pub fn pad_x_needed(label: &str, what: &str, found: &str) -> HostError {
    HostError::Input(format!(
        "{label}: {what}: no pad_x: pad_x is needed, every analysis starts from the pad's x acceleration (name a column or record pad_x, or give --channel pad_x=SOURCE[*SCALE]; found: {found})"
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(a: &[&str]) -> Result<ChannelMap> {
        ChannelMap::parse(&a.iter().map(|s| s.to_string()).collect::<Vec<_>>())
    }

    #[test]
    fn forms() {
        let m = p(&["pad_x=Acc1 [g]", "disc_x=#3*9.80665", "Pad Lead=acc2*-2"]).unwrap();
        assert_eq!(m.specs[0], ChannelSpec { key: 1, source: ChannelSource::Name("Acc1 [g]".into()), scale: None, arg: "pad_x=Acc1 [g]".into() });
        assert_eq!(m.specs[1].source, ChannelSource::Index(3));
        assert_eq!(m.specs[1].scale, Some(9.80665));
        assert_eq!(m.specs[2].key, 3);
        assert_eq!(m.specs[2].scale, Some(-2.0));
        for bad in [&["pad_x"][..], &["x=a"], &["pad_x=#0"], &["pad_x=a*0"], &["pad_x=a*b"], &["pad_x="], &["pad_x=a", "pad_x=b"], &["pad_x=a", "disc_x=A"]] {
            assert!(p(bad).is_err(), "{bad:?}");
        }
    }
}
