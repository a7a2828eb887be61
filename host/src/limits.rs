//! What the tool accepts at most: the size of every small file it reads whole (scene, fit
//! table, map shard, firmware ELF; recordings and defmt streams stream and are not bounded
//! here), the counts a user gives (map cells, sweep values, shards, profile points, fit
//! starts, ...), and the work budget of one run. One place, so that `--help`, the errors and
//! the campaign of bad inputs (scripts/bad-inputs.sh) agree.
//!
//! A file is read with a bounded reader: at most its limit plus one byte is ever held, so
//! `/dev/zero` or a multi-gigabyte file given as a scene fails after reading 1 MiB, not after
//! filling the memory.

use std::io::Read;
use std::path::Path;

use crate::error::{HostError, Result};

/// Largest scene file [bytes] (a complete scene file is about 4 KiB).
pub const SCENE_FILE_MAX_BYTES: u64 = 1 << 20;
/// Largest fit table (`fit --table`) [bytes] (Table 3.1 is about 1 KiB).
pub const TABLE_FILE_MAX_BYTES: u64 = 1 << 20;
/// Largest map shard (`map merge`) [bytes]: about 90,000 cells; split bigger maps into more
/// shards.
pub const SHARD_FILE_MAX_BYTES: u64 = 64 << 20;
/// Largest firmware ELF (`decode --elf`) [bytes] (the rig firmware's, with debug info, is
/// about 2 MB).
pub const ELF_FILE_MAX_BYTES: u64 = 64 << 20;

/// Most values of one `map --sweep` (N).
pub const SWEEP_MAX_N: usize = 100_000;
/// Most cells of a map (the product of its sweeps' N).
pub const MAP_MAX_CELLS: usize = 10_000_000;
/// Most points of `fit --profile KEY=LO:HI:N`.
pub const PROFILE_MAX_POINTS: usize = 1_000;
/// Most starts of `fit --starts`.
pub const FIT_MAX_STARTS: usize = 1_000;
/// Most bootstrap resamples of `fit --bootstrap`.
pub const FIT_MAX_BOOTSTRAP: usize = 100_000;
/// Most iterations of `fit --max-iters`.
pub const FIT_MAX_ITERS: u64 = 1_000_000;
/// Longest quiet lead of `sil --quiet-lead` [s].
pub const QUIET_LEAD_MAX_S: f64 = 60.0;
/// Largest sensor noise of `sil --noise` [m/s^2 rms]: the ADC's whole range.
pub const NOISE_MAX_M_S2: f64 = 1e4;
/// Front-end gain range of `sil --gain` [V/V].
pub const GAIN_RANGE: (f64, f64) = (1e-3, 1e3);
/// Largest converter noise of `--adc-noise` [counts rms] (the 12-bit ADC's range).
pub const ADC_NOISE_MAX_COUNTS: f64 = 4096.0;
/// Largest `--breakaway-jump` [m/s^2] (far beyond the rig's 700 m/s^2 range).
pub const BREAKAWAY_JUMP_MAX_M_S2: f64 = 1e6;
/// Most worker threads of `map --jobs`.
pub const MAX_JOBS: usize = 1024;

/// Work budget of one run: substeps per step (the quarter-radian rule of the exact steppers:
/// the fastest mode turns by at most a quarter radian per substep) times the steps, at most
/// 2^27 (134,217,728: a 5,243 s run at 25.6 kHz and one substep per step, about 10 s of
/// computing; a substep of the model-2 stepper in Stribeck slip costs up to 1 us). A run over
/// it is halted before its first step with the outcome `budget`.
pub const SUBSTEP_BUDGET: u64 = 1 << 27;
/// Most substeps per step: a scene whose fastest mode turns by more than 1024 radians in one
/// step (`k_b = 1e18` on the rig's band: 1.6e5 substeps per step, 200 s for 0.05 s of motion)
/// is not run (outcome `budget`); the steppers' own cap is 1e6, beyond which their tables
/// would break the quarter-radian rule.
pub const SUBSTEPS_PER_STEP_CAP: u32 = 4096;

fn mib(bytes: u64) -> String {
    if bytes % (1 << 20) == 0 {
        format!("{} MiB", bytes >> 20)
    } else {
        format!("{bytes} bytes")
    }
}

/// Reads at most `limit` bytes of `path` (`what` names it in errors: "scene file", ...):
/// past the limit, one line naming the file, the limit and the rule.
pub fn read_bytes(path: &Path, what: &str, limit: u64) -> Result<Vec<u8>> {
    let shown = path.display();
    let f = std::fs::File::open(path).map_err(|e| HostError::Input(format!("{shown}: cannot read the {what}: {e}")))?;
    if let Ok(md) = f.metadata() {
        if md.is_dir() {
            return Err(HostError::Input(format!("{shown}: cannot read the {what}: it is a directory")));
        }
        if md.is_file() && md.len() > limit {
            return Err(too_big(path, what, limit));
        }
    }
    let mut buf = Vec::new();
    f.take(limit + 1)
        .read_to_end(&mut buf)
        .map_err(|e| HostError::Input(format!("{shown}: cannot read the {what}: {e}")))?;
    if buf.len() as u64 > limit {
        return Err(too_big(path, what, limit));
    }
    Ok(buf)
}

/// [`read_bytes`] as UTF-8 text.
pub fn read_text(path: &Path, what: &str, limit: u64) -> Result<String> {
    let bytes = read_bytes(path, what, limit)?;
    String::from_utf8(bytes).map_err(|e| {
        HostError::Input(format!(
            "{}: cannot read the {what}: not UTF-8 text (invalid byte at offset {})",
            path.display(),
            e.utf8_error().valid_up_to()
        ))
    })
}

fn too_big(path: &Path, what: &str, limit: u64) -> HostError {
    HostError::Input(format!(
        "{}: the {what} is larger than {}: a {what} is at most {} (see --help)",
        path.display(),
        mib(limit),
        mib(limit)
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// /dev/zero is cut at the limit, a small file passes whole.
    #[test]
    fn reads_stop_at_the_limit() {
        let dir = std::env::temp_dir().join(format!("stickslip-limits-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let small = dir.join("small.toml");
        std::fs::write(&small, "m = 1.0\n").unwrap();
        assert_eq!(read_text(&small, "scene file", 8).unwrap(), "m = 1.0\n");
        let e = read_text(&small, "scene file", 7).unwrap_err().to_string();
        assert!(e.contains("larger than 7 bytes"), "{e}");
        if Path::new("/dev/zero").exists() {
            let e = read_bytes(Path::new("/dev/zero"), "scene file", 1 << 10).unwrap_err().to_string();
            assert!(e.contains("/dev/zero") && e.contains("larger than"), "{e}");
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
