//! Arrays of exactly their size: a point is `[x, y]`, never `[x, y, 999]`.
//!
//! serde reads a `[f64; 2]` from a longer TOML array and drops the rest; [`Fixed`] refuses it.

use std::fmt;
use std::marker::PhantomData;

use serde::de::{Deserialize, Deserializer, Error, IgnoredAny, SeqAccess, Visitor};

/// An array of exactly `N` values, read from a sequence of exactly `N` elements.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fixed<T, const N: usize>(pub [T; N]);

impl<'de, T: Deserialize<'de> + Copy + Default, const N: usize> Deserialize<'de> for Fixed<T, N> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V<T, const N: usize>(PhantomData<T>);
        impl<'de, T: Deserialize<'de> + Copy + Default, const N: usize> Visitor<'de> for V<T, N> {
            type Value = Fixed<T, N>;

            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                write!(f, "an array of exactly {N} numbers")
            }

            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
                let mut out = [T::default(); N];
                for (i, slot) in out.iter_mut().enumerate() {
                    *slot = seq
                        .next_element()?
                        .ok_or_else(|| A::Error::invalid_length(i, &self))?;
                }
                if seq.next_element::<IgnoredAny>()?.is_some() {
                    let mut n = N + 1;
                    while seq.next_element::<IgnoredAny>()?.is_some() {
                        n += 1;
                    }
                    return Err(A::Error::invalid_length(n, &self));
                }
                Ok(Fixed(out))
            }
        }
        d.deserialize_seq(V::<T, N>(PhantomData))
    }
}

impl<T, const N: usize> From<Fixed<T, N>> for [T; N] {
    fn from(f: Fixed<T, N>) -> [T; N] {
        f.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(serde::Deserialize, Debug)]
    #[allow(dead_code)]
    struct T {
        p: Fixed<f64, 2>,
    }

    #[test]
    fn arrays_have_exactly_their_size() {
        let t: T = toml::from_str("p = [1.0, 2]").unwrap();
        assert_eq!(t.p, Fixed([1.0, 2.0]));
        let e = toml::from_str::<T>("p = [4, 4, 999]").unwrap_err();
        assert!(
            e.message()
                .contains("invalid length 3, expected an array of exactly 2"),
            "{e}"
        );
        assert!(toml::from_str::<T>("p = [4]").is_err());
    }
}
