//! The calling thread's CPU time: what a computation costs on a core of its own, whatever else
//! the machine runs (its wall time grows with the load; its CPU time does not).

/// CPU time the calling thread has used so far (s), where the platform reports it (Unix:
/// `clock_gettime(CLOCK_THREAD_CPUTIME_ID)`); `None` elsewhere.
pub fn thread_cpu_s() -> Option<f64> {
    #[cfg(unix)]
    {
        let mut ts = libc::timespec {
            tv_sec: 0,
            tv_nsec: 0,
        };
        // SAFETY: clock_gettime writes one timespec through a pointer to a live local.
        let rc = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
        (rc == 0).then_some(ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9)
    }
    #[cfg(not(unix))]
    {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The clock runs while the thread computes and never runs backwards.
    #[cfg(unix)]
    #[test]
    fn thread_cpu_time_grows_with_work() {
        let a = thread_cpu_s().unwrap();
        let mut x = 0u64;
        let mut b = a;
        while b <= a {
            for i in 0..100_000u64 {
                x = x.wrapping_mul(6364136223846793005).wrapping_add(i);
            }
            b = thread_cpu_s().unwrap();
        }
        assert!(b > a && x != 1);
    }
}
