//! CPU time the hypervisor took from this virtual machine ("steal"), so
//! that timings on a shared cloud machine can be corrected for it.
//!
//! On the project's 2-core virtual machines steal reaches 20–45 % of a
//! render's wall time at busy hours (`vmstat`'s `st` column), which would
//! make rpbrt look that much slower than pbrt-v4's figures, measured on a
//! quiet machine. The correction subtracts from a wall-clock interval the
//! time the machine's CPUs were stolen during it, averaged over the CPUs.

/// A reading of the machine's cumulative steal.
#[derive(Clone, Copy, Debug)]
pub struct StealClock {
    /// Stolen time summed over CPUs, seconds (0 where not available).
    stolen_cpu_seconds: f64,
    cpus: usize,
}

/// `/proc/stat` counts in USER_HZ, which Linux fixes at 100 per second for
/// user space.
const TICKS_PER_SECOND: f64 = 100.0;

impl StealClock {
    pub fn now() -> StealClock {
        std::fs::read_to_string("/proc/stat")
            .ok()
            .and_then(|text| parse_proc_stat(&text))
            .unwrap_or(StealClock {
                stolen_cpu_seconds: 0.0,
                cpus: 1,
            })
    }

    /// Wall-clock seconds lost to steal since `self`: stolen CPU time
    /// averaged over the machine's CPUs.
    pub fn stolen_since(&self, later: &StealClock) -> f64 {
        ((later.stolen_cpu_seconds - self.stolen_cpu_seconds) / self.cpus.max(1) as f64).max(0.0)
    }
}

/// Runs `work` and times it: (its result, wall seconds less the time
/// stolen meanwhile, the stolen seconds).
pub fn time_without_steal<T>(work: impl FnOnce() -> T) -> (T, f64, f64) {
    let (start, steal) = (std::time::Instant::now(), StealClock::now());
    let result = work();
    let wall = start.elapsed().as_secs_f64();
    let stolen = steal.stolen_since(&StealClock::now()).min(wall);
    (result, wall - stolen, stolen)
}

/// The aggregate `cpu` line's 8th value (steal) and the number of `cpuN`
/// lines.
fn parse_proc_stat(text: &str) -> Option<StealClock> {
    let total = text.lines().find(|l| l.starts_with("cpu "))?;
    let steal: f64 = total.split_whitespace().nth(8)?.parse().ok()?;
    let cpus = text
        .lines()
        .filter(|l| l.starts_with("cpu") && l.as_bytes().get(3).is_some_and(u8::is_ascii_digit))
        .count();
    Some(StealClock {
        stolen_cpu_seconds: steal / TICKS_PER_SECOND,
        cpus: cpus.max(1),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_steal_and_cpu_count() {
        let before = "cpu  10 0 5 100 0 0 0 40 0 0\ncpu0 5 0 2 50 0 0 0 20 0 0\ncpu1 5 0 3 50 0 0 0 20 0 0\nintr 1\n";
        let after = "cpu  10 0 5 100 0 0 0 240 0 0\ncpu0 5 0 2 50 0 0 0 120 0 0\ncpu1 5 0 3 50 0 0 0 120 0 0\n";
        let (a, b) = (
            parse_proc_stat(before).unwrap(),
            parse_proc_stat(after).unwrap(),
        );
        assert_eq!(a.cpus, 2);
        // 200 ticks over 2 CPUs: 1 s of wall time lost.
        assert!((a.stolen_since(&b) - 1.0).abs() < 1e-12);
        assert!(parse_proc_stat("intr 1\n").is_none());
    }
}
