//! The grid of a map: one or two swept scene keys, `KEY=FROM:TO:N[:log]`, and the scene of
//! each cell.

use serde::{Deserialize, Serialize};
use stickslip_model::Scene;

use crate::scenes::scene_file;

/// One swept key: N values from FROM to TO, evenly spaced (or geometrically with `log`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Sweep {
    pub key: String,
    pub from: f64,
    pub to: f64,
    pub n: usize,
    pub log: bool,
}

impl Sweep {
    /// Reads `KEY=FROM:TO:N[:log]`. The error names the sweep and the rule.
    pub fn parse(arg: &str) -> Result<Sweep, String> {
        let bad = |rule: String| Err(format!("--sweep {arg}: {rule}"));
        let Some((key, range)) = arg.split_once('=') else {
            return bad("expected KEY=FROM:TO:N or KEY=FROM:TO:N:log".into());
        };
        let key = key.trim();
        if !scene_file::NUMERIC_KEYS.contains(&key) {
            return bad(format!("unknown numeric scene key `{key}` (the numeric keys: {})", scene_file::NUMERIC_KEYS.join(", ")));
        }
        let parts: Vec<&str> = range.split(':').map(str::trim).collect();
        let log = match parts.len() {
            3 => false,
            4 if parts[3] == "log" => true,
            4 => return bad(format!("`{}`: the fourth field can only be `log`", parts[3])),
            _ => return bad("expected KEY=FROM:TO:N or KEY=FROM:TO:N:log".into()),
        };
        let num = |name: &str, s: &str| -> Result<f64, String> {
            match s.parse::<f64>() {
                Ok(v) if v.is_finite() => Ok(v),
                _ => Err(format!("--sweep {arg}: {name} `{s}` is not a finite number")),
            }
        };
        let from = num("FROM", parts[0])?;
        let to = num("TO", parts[1])?;
        let n: usize = match parts[2].parse() {
            Ok(n) if (1..=crate::limits::SWEEP_MAX_N).contains(&n) => n,
            _ => {
                return bad(format!(
                    "N `{}` must be a whole number >= 1 (at most {} values in one sweep)",
                    parts[2],
                    crate::limits::SWEEP_MAX_N
                ))
            }
        };
        if n >= 2 && from == to {
            return bad(format!("FROM = TO = {from} with N = {n}: give N = 1 or a range"));
        }
        if n == 1 && from != to {
            return bad(format!("N = 1 runs one value, but FROM = {from} and TO = {to} differ: give {from}:{from}:1, or N >= 2 for the range"));
        }
        if log && !(from > 0.0 && to > 0.0) {
            return bad("a log sweep needs FROM > 0 and TO > 0".into());
        }
        if log && from > to {
            return bad(format!("a log sweep needs FROM <= TO (got {from} > {to})"));
        }
        Ok(Sweep { key: key.to_string(), from, to, n, log })
    }

    /// The i-th value, i in 0..n: FROM + i (TO - FROM) / (N - 1), or FROM (TO / FROM)^(i / (N - 1))
    /// for a log sweep; the last value is TO exactly.
    pub fn value(&self, i: usize) -> f64 {
        if self.n == 1 {
            return self.from;
        }
        if i + 1 == self.n {
            return self.to;
        }
        let f = i as f64 / (self.n - 1) as f64;
        if self.log {
            self.from * (self.to / self.from).powf(f)
        } else {
            self.from + f * (self.to - self.from)
        }
    }

    /// As given on the command line.
    pub fn spec(&self) -> String {
        format!("{}={}:{}:{}{}", self.key, self.from, self.to, self.n, if self.log { ":log" } else { "" })
    }
}

/// The cells: the product of the sweeps, the first sweep running fastest (cell index
/// i = i_1 + n_1 i_2).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Grid {
    pub sweeps: Vec<Sweep>,
    /// Damping ratios the base scene's file gave (`zeta_x`, `zeta_phi`, `zeta_b`), held in
    /// every cell: each cell's coefficient from its own stiffness and inertia
    /// ([`Grid::holding_ratios`]; empty: the base scene's coefficients are kept).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub held_ratios: Vec<(String, f64)>,
}

impl Grid {
    /// One or two sweeps of different keys.
    pub fn new(sweeps: Vec<Sweep>) -> Result<Grid, String> {
        match sweeps.len() {
            0 => return Err("map: give one or two --sweep KEY=FROM:TO:N[:log]".into()),
            1 | 2 => {}
            n => return Err(format!("map: {n} sweeps given: a map sweeps one or two keys")),
        }
        if sweeps.len() == 2 && scene_file::field_of(&sweeps[0].key) == scene_file::field_of(&sweeps[1].key) {
            return Err(format!(
                "--sweep {} and --sweep {}: both set `{}`",
                sweeps[0].spec(),
                sweeps[1].spec(),
                scene_file::field_of(&sweeps[0].key)
            ));
        }
        let cells = sweeps.iter().fold(1usize, |c, s| c.saturating_mul(s.n));
        if cells > crate::limits::MAP_MAX_CELLS {
            return Err(format!(
                "--sweep {}: {cells} cells, more than a map's {} (split the ranges into several maps)",
                sweeps.iter().map(Sweep::spec).collect::<Vec<_>>().join(" --sweep "),
                crate::limits::MAP_MAX_CELLS
            ));
        }
        Ok(Grid { sweeps, held_ratios: Vec::new() })
    }

    /// The grid with the damping ratios a scene file gave held in every cell: a file that says
    /// `zeta_x = 0.05` means that ratio at every k_g and m the map sweeps, not the c_x it comes
    /// to at the file's own k_g ([`crate::scenes::scene_source::file_ratios`], given the swept
    /// keys: a ratio whose key or coefficient is swept is the sweep's).
    pub fn holding_ratios(mut self, ratios: Vec<(String, f64)>) -> Grid {
        self.held_ratios = ratios;
        self
    }

    /// The swept keys, in sweep order.
    pub fn keys(&self) -> Vec<&str> {
        self.sweeps.iter().map(|w| w.key.as_str()).collect()
    }

    pub fn cells(&self) -> usize {
        self.sweeps.iter().map(|s| s.n).product()
    }

    /// The sweep indices of cell `i`.
    pub fn coords(&self, i: usize) -> Vec<usize> {
        let mut rest = i;
        self.sweeps
            .iter()
            .map(|s| {
                let c = rest % s.n;
                rest /= s.n;
                c
            })
            .collect()
    }

    /// (key, value) of cell `i`, in sweep order.
    pub fn params(&self, i: usize) -> Vec<(String, f64)> {
        self.coords(i).iter().zip(&self.sweeps).map(|(&c, s)| (s.key.clone(), s.value(c))).collect()
    }

    /// The scene of cell `i`: `base` with the cell's values (damping ratios last, swept or
    /// held ([`Grid::holding_ratios`]), so that they use the cell's stiffness), validated (with a pneumatic drive, also the throttle's solve
    /// from v: a supply too low for the cell's load). The error names the field and the rule.
    pub fn scene(&self, base: &Scene, i: usize) -> Result<Scene, String> {
        let mut s = *base;
        let mut params = self.params(i);
        params.sort_by_key(|(k, _)| k.starts_with("zeta_"));
        for (k, v) in &params {
            scene_file::set_numeric(&mut s, k, *v)?;
        }
        for (k, v) in &self.held_ratios {
            scene_file::set_numeric(&mut s, k, *v)?;
        }
        let named = |e: stickslip_model::SceneError| format!("field `{}` = {}: {}", e.field, scene_file::rejected_value(&s, &e), e.rule);
        s.validate().map_err(named)?;
        // a pneumatic drive whose supply cannot push the cell's load at v (the throttle's solve)
        stickslip_model::model3::cylinder::small_signal_scene(&s).map_err(named)?;
        Ok(s)
    }

    /// A sweep value that makes every cell it takes part in invalid is a bad sweep (no other
    /// sweep's value rescues it): the error names the sweep, the value and the first cell's
    /// reason. Cells invalid only in combination are reported per cell.
    pub fn check(&self, base: &Scene) -> Result<(), String> {
        // a key that does nothing in the base scene (and no other sweep makes it act)
        for sw in &self.sweeps {
            let enabled_by_other = sw.key == "c_y" && self.sweeps.iter().any(|o| o.key == "k_pivot");
            if let (Some(why), false) = (scene_file::inert_key(base, &sw.key), enabled_by_other) {
                return Err(format!("--sweep {}: `{}` does nothing in the base scene: {why}", sw.spec(), sw.key));
            }
        }
        let mut any_ok: Vec<Vec<bool>> = self.sweeps.iter().map(|s| vec![false; s.n]).collect();
        for i in 0..self.cells() {
            if self.scene(base, i).is_ok() {
                for (d, c) in self.coords(i).into_iter().enumerate() {
                    any_ok[d][c] = true;
                }
            }
        }
        for (d, sw) in self.sweeps.iter().enumerate() {
            if let Some(j) = any_ok[d].iter().position(|ok| !ok) {
                let why = (0..self.cells())
                    .find(|&i| self.coords(i)[d] == j)
                    .and_then(|i| self.scene(base, i).err())
                    .unwrap_or_default();
                return Err(format!("--sweep {}: {} = {}: the scene rejects it: {why}", sw.spec(), sw.key, crate::output::format::short(sw.value(j))));
            }
        }
        Ok(())
    }
}
