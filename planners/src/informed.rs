//! Informed sampling.
