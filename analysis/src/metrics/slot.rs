//! An optional number in eight bytes, for the per-run tables that hold one slot per metric.

/// The bit pattern of an empty slot: a signalling NaN, which no arithmetic or parsing gives
/// (both give quiet NaNs).
const NONE: u64 = 0x7ff4_0000_0000_0001;

/// An `Option<f64>` in eight bytes: `None` is one signalling NaN's bit pattern, every other
/// value (quiet NaNs and infinities too) is kept as it is.
#[derive(Clone, Copy)]
pub struct Slot(u64);

impl Slot {
    /// An empty slot.
    pub const EMPTY: Slot = Slot(NONE);

    /// The slot of `v`.
    pub fn new(v: Option<f64>) -> Slot {
        v.map_or(Slot::EMPTY, |x| Slot(x.to_bits()))
    }

    /// The value it holds.
    pub fn get(self) -> Option<f64> {
        (self.0 != NONE).then(|| f64::from_bits(self.0))
    }
}

impl Default for Slot {
    fn default() -> Self {
        Slot::EMPTY
    }
}

/// Equal as the options they hold are (a NaN equals no value).
impl PartialEq for Slot {
    fn eq(&self, other: &Self) -> bool {
        self.get() == other.get()
    }
}

impl std::fmt::Debug for Slot {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.get().fmt(f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_slot_gives_back_what_it_was_given() {
        for v in [
            None,
            Some(0.0),
            Some(-0.0),
            Some(1.5e-300),
            Some(f64::INFINITY),
            Some(f64::NEG_INFINITY),
            Some(f64::MAX),
        ] {
            assert_eq!(Slot::new(v).get().map(f64::to_bits), v.map(f64::to_bits));
        }
        let nan = Slot::new(Some(f64::NAN)).get();
        assert!(nan.is_some_and(f64::is_nan));
        assert!(Slot::new("NaN".parse().ok()).get().is_some());
        let zero = std::hint::black_box(0.0f64);
        assert!((f64::NAN * 2.0).to_bits() != NONE && (zero / zero).to_bits() != NONE);
        assert!((f64::INFINITY - f64::INFINITY).to_bits() != NONE);
        assert_eq!(std::mem::size_of::<Slot>(), 8);
    }
}
