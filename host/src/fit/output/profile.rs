//! Markdown and JSON of a cost profile (`fit --profile`).

use super::*;

/// `fit --profile --json`.
#[derive(Serialize)]
pub struct ProfileJson<'a> {
    pub scene: &'a str,
    pub key: &'a str,
    pub others: BTreeMap<&'a str, f64>,
    pub statistics: usize,
    /// "statistics" (log ratios of the statistics) or "time_domain" (the recordings' samples).
    pub cost: &'static str,
    /// The time-domain cost's residual count; null for the statistics' cost.
    pub residuals: Option<usize>,
    pub points: Vec<ProfilePointJson<'a>>,
    pub seconds: f64,
}

#[derive(Serialize)]
pub struct ProfilePointJson<'a> {
    pub value: f64,
    pub cost: Option<f64>,
    pub rms_log_ratio: Option<f64>,
    pub worst: Option<&'a str>,
    pub worst_log_ratio: Option<f64>,
    pub error: Option<&'a str>,
}

impl<'a> ProfileJson<'a> {
    pub fn new(p: &'a super::super::Profile) -> Self {
        ProfileJson {
            scene: &p.scene,
            key: &p.key,
            others: p.others.iter().map(|(k, v)| (k.as_str(), *v)).collect(),
            statistics: p.statistics,
            cost: if p.time_domain_residuals.is_some() { "time_domain" } else { "statistics" },
            residuals: p.time_domain_residuals,
            points: p
                .points
                .iter()
                .map(|q| ProfilePointJson {
                    value: q.value,
                    cost: q.cost,
                    rms_log_ratio: q.rms_log_ratio,
                    worst: q.worst.as_ref().map(|w| w.0.as_str()),
                    worst_log_ratio: q.worst.as_ref().map(|w| w.1),
                    error: q.error.as_deref(),
                })
                .collect(),
            seconds: p.seconds,
        }
    }
}

/// `fit --profile` as Markdown.
pub fn profile_markdown(p: &super::super::Profile) -> String {
    let what = match p.time_domain_residuals {
        Some(n) => format!(
            "Time-domain cost: {n} residuals (the recordings' samples and cycle timings in units of their noise); cost = sum of their squares / 2, as the fit minimises it"
        ),
        None => format!("{} statistics; cost = sum of the squared weighted log ratios / 2, as the fit minimises it", p.statistics),
    };
    let mut o = format!(
        "# Cost profile of scene `{}` along {}\n\n{what}; {}; {} points in {:.1} s.\n\n",
        p.scene,
        p.key,
        if p.others.is_empty() {
            "no other free key".to_string()
        } else {
            format!(
                "the other free keys at the scene's values ({})",
                p.others.iter().map(|(k, v)| format!("{k} = {}", num(*v))).collect::<Vec<_>>().join(", ")
            )
        },
        p.points.len(),
        p.seconds
    );
    if p.time_domain_residuals.is_some() {
        // no statistics: no log ratios to show
        o.push_str(&format!("| {} | cost | |\n|---:|---:|---|\n", p.key));
        for q in &p.points {
            match (&q.cost, &q.error) {
                (Some(c), _) => o.push_str(&format!("| {} | {c:.6e} | |\n", num(q.value))),
                (None, e) => o.push_str(&format!("| {} | rejected | {} |\n", num(q.value), e.as_deref().unwrap_or("-"))),
            }
        }
        return o;
    }
    o.push_str(&format!("| {} | cost | RMS ln ratio | largest ln ratio | of |\n|---:|---:|---:|---:|---|\n", p.key));
    for q in &p.points {
        match (&q.cost, &q.error) {
            (Some(c), _) => {
                let (w, x) = q.worst.as_ref().map_or(("-".to_string(), "-".to_string()), |(l, x)| (l.clone(), format!("{x:+.4}")));
                o.push_str(&format!("| {} | {c:.6e} | {:.4} | {x} | {w} |\n", num(q.value), q.rms_log_ratio.unwrap_or(f64::NAN)));
            }
            (None, e) => o.push_str(&format!("| {} | rejected | - | - | {} |\n", num(q.value), e.as_deref().unwrap_or("-"))),
        }
    }
    o
}
