//! The starts of a search: Halton points over the bounds' box, screened by their cost, the best
//! points kept apart from each other ([`screened_starts`]).

use super::*;

/// Bases of the Halton sequence, one per free key.
pub(super) const HALTON_BASES: [u32; 12] = [2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37];

/// Element `k` of the Halton sequence in base `b`, in [0, 1).
pub(super) fn halton(mut k: u32, b: u32) -> f64 {
    let (mut f, mut x) = (1.0, 0.0);
    while k > 0 {
        f /= b as f64;
        x += f * (k % b) as f64;
        k /= b;
    }
    x
}

/// Points 1 ..= `count` of the Halton sequence in `dim` dimensions (base [`HALTON_BASES`]`[i]`
/// in dimension i), in the unit box [0, 1)^dim: the screen's points and the polish's
/// neighbourhood are these, mapped onto their boxes.
pub(super) fn halton_unit_points(count: usize, dim: usize) -> impl Iterator<Item = Vec<f64>> {
    (1..=count).map(move |k| (0..dim).map(|i| halton(k as u32, HALTON_BASES[i % HALTON_BASES.len()])).collect())
}

/// Screen of the first horizon stage: this many points per free key, spread over
/// start / [`SCREEN_FACTOR`] .. start x [`SCREEN_FACTOR`] by a Halton sequence.
pub const SCREEN_POINTS_PER_KEY: usize = 64;
/// Half-width of the screen, as a factor on each start value.
pub const SCREEN_FACTOR: f64 = 2.0;

/// Global stage over the whole box of the bounds: this many Halton points per free key on
/// the time-domain cost (cheap: one slip per evaluation).
pub const GLOBAL_POINTS_PER_KEY: usize = 256;
/// Global stage on a table's statistics (each point runs every case).
pub const TABLE_POINTS_PER_KEY: usize = 24;
/// Two starts taken from a screen differ by at least this in some ln p.
pub const START_SEPARATION: f64 = 0.05;

/// The starts of a search: the scene's values (u = 0) and the `starts - 1` lowest-cost points
/// of a Halton screen of `first` (`per_key` points per free key), at least
/// [`START_SEPARATION`] apart. The screen spans the whole box of the bounds (`span` `None`: the
/// global stage) or a factor e^span either way of each start, inside the bounds (the horizon
/// stages' screen). No screen for a single start.
pub fn screened_starts(first: &Problem, starts: usize, span: Option<f64>, per_key: usize) -> Vec<Vec<f64>> {
    let n = first.free.len();
    if starts <= 1 {
        return vec![vec![0.0; n]];
    }
    let t0 = std::time::Instant::now();
    // the box in u = ln(p / p_start): the bounds, or e^span either way inside them
    let sides: Vec<(f64, f64)> = first
        .free
        .iter()
        .map(|f| {
            let (mut a, mut b) = f.u_range();
            if let Some(sp) = span {
                a = a.max(-sp);
                b = b.min(sp);
            }
            (a, b)
        })
        .collect();
    let screen: Vec<Vec<f64>> = halton_unit_points(per_key * n, n)
        .map(|h| h.iter().zip(&sides).map(|(h, (a, b))| a + (b - a) * h).collect())
        .collect();
    let costs: Vec<f64> = screen.par_iter().map(|u| first.residuals(u).map_or(OUTSIDE, |r| cost_of(&r))).collect();
    let mut order: Vec<usize> = (0..screen.len()).filter(|&i| costs[i] < OUTSIDE).collect();
    order.sort_by(|&a, &b| costs[a].total_cmp(&costs[b]));
    eprintln!(
        "fit: {} of {} points in {:.1} s ({} valid), lowest cost {:.4e}",
        if span.is_none() { "global screen over the bounds" } else { "screen of the first horizon" },
        screen.len(),
        t0.elapsed().as_secs_f64(),
        order.len(),
        order.first().map_or(f64::NAN, |&i| costs[i])
    );
    let mut out = vec![vec![0.0; n]];
    for i in order {
        if out.len() >= starts {
            break;
        }
        let far = out[1..].iter().all(|o| o.iter().zip(&screen[i]).any(|(a, b)| (a - b).abs() >= START_SEPARATION));
        if far {
            out.push(screen[i].clone());
        }
    }
    out
}
