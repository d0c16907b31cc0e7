//! A deterministic mutator for text inputs: the same seed gives the same input, on any machine.
//!
//! It knows just enough of TOML and JSON to reach the validators, not only the syntax checks:
//! besides byte flips, cuts and splices it swaps numbers and strings for boundary values
//! (±1e308, NaN, ±inf, i64 extremes, 0, tiny steps), duplicates, drops and grows lines and
//! arrays, and truncates. Each input stacks one to four mutations on a seed.

use rand::{Rng, RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Numbers that broke (or could break) a validator: overflow, underflow, sign, NaN, infinity,
/// integer extremes, and the values of known reproducers (env/tests/integration/scenarios.rs).
const NUMBERS: &[&str] = &[
    "0",
    "-0",
    "0.0",
    "-1",
    "1",
    "2",
    "0.5",
    "1e308",
    "-1e308",
    "1e-308",
    "5e-324",
    "1e400",
    "nan",
    "-nan",
    "inf",
    "-inf",
    "9223372036854775807",
    "-9223372036854775808",
    "18446744073709551615",
    "1e20",
    "1e-12",
    "1e10",
    "1e11",
    "100000000000",
    "4294967296",
    "65536",
    "0.016666666666666666",
    "3.141592653589793",
];

/// Strings for string values: empty, path-like, long, odd characters, other formats' words.
const STRINGS: &[&str] = &[
    "",
    ".",
    "..",
    "/",
    "/dev/null",
    "a/b",
    "results",
    "é",
    "\\u0000",
    "goal-zoom-rrt{k=0}",
    "sst{pruning_radius=-1}",
    "obc{w_com=nan}",
    "fake",
    "realistic",
    "ideal",
    "serial",
    "recorded",
    "emulator",
    "v4l2",
    "dark",
    "bright",
];

/// One mutated input from `seed` (drawn as the `index`-th input of stream `stream`); `corpus`
/// gives material to splice in.
pub fn mutate(stream: u64, index: u64, seed: &str, corpus: &[String]) -> Vec<u8> {
    let mut rng = ChaCha8Rng::seed_from_u64(stream);
    rng.set_stream(index);
    let mut data = seed.as_bytes().to_vec();
    for _ in 0..rng.random_range(1..=4) {
        match rng.random_range(0..12) {
            0..=2 => replace_token(&mut rng, &mut data, is_number_start, NUMBERS),
            3 => replace_token(&mut rng, &mut data, |b| b == b'"', STRINGS),
            4 => line_edit(&mut rng, &mut data),
            5 => grow_array(&mut rng, &mut data),
            6 => {
                // flip a bit
                if !data.is_empty() {
                    let i = rng.random_range(0..data.len());
                    data[i] ^= 1 << rng.random_range(0..8);
                }
            }
            7 => {
                // delete a range
                if !data.is_empty() {
                    let a = rng.random_range(0..data.len());
                    let b = (a + rng.random_range(1..=16)).min(data.len());
                    data.drain(a..b);
                }
            }
            8 => {
                // insert a byte that matters to the syntax
                let b = *pick(&mut rng, b"[]{}=,.\"'#\n-+ 0eE\\");
                let i = rng.random_range(0..=data.len());
                data.insert(i, b);
            }
            9 => {
                // splice a piece of another corpus entry
                if let Some(other) = corpus.get(rng.random_range(0..corpus.len().max(1))) {
                    let o = other.as_bytes();
                    if !o.is_empty() {
                        let a = rng.random_range(0..o.len());
                        let b = (a + rng.random_range(1..=200)).min(o.len());
                        let i = rng.random_range(0..=data.len());
                        data.splice(i..i, o[a..b].iter().copied());
                    }
                }
            }
            10 => {
                // truncate
                let n = rng.random_range(0..=data.len());
                data.truncate(n);
            }
            _ => {
                // a number digit changed
                let digits: Vec<usize> = (0..data.len())
                    .filter(|&i| data[i].is_ascii_digit())
                    .collect();
                if !digits.is_empty() {
                    let i = *pick(&mut rng, &digits);
                    data[i] = b'0' + rng.random_range(0..10);
                }
            }
        }
    }
    data
}

fn pick<'a, T>(rng: &mut impl Rng, v: &'a [T]) -> &'a T {
    &v[rng.random_range(0..v.len())]
}

fn is_number_start(b: u8) -> bool {
    b.is_ascii_digit() || b == b'-'
}

/// Replaces one token starting with a byte `starts` accepts by one of `values`.
fn replace_token(rng: &mut impl Rng, data: &mut Vec<u8>, starts: fn(u8) -> bool, values: &[&str]) {
    let starts_at: Vec<usize> = (0..data.len())
        .filter(|&i| starts(data[i]) && (i == 0 || !data[i - 1].is_ascii_alphanumeric()))
        .collect();
    if starts_at.is_empty() {
        return;
    }
    let a = *pick(rng, &starts_at);
    let b = if data[a] == b'"' {
        // a string: up to its closing quote
        data[a + 1..]
            .iter()
            .position(|c| *c == b'"')
            .map_or(data.len(), |k| a + 1 + k + 1)
    } else {
        a + data[a..]
            .iter()
            .position(|c| !(c.is_ascii_alphanumeric() || b"+-._".contains(c)))
            .unwrap_or(data.len() - a)
    };
    let v = *pick(rng, values);
    let v = if data[a] == b'"' {
        format!("\"{v}\"")
    } else {
        v.to_string()
    };
    data.splice(a..b, v.bytes());
}

/// Duplicates, drops or swaps whole lines.
fn line_edit(rng: &mut impl Rng, data: &mut Vec<u8>) {
    let text = String::from_utf8_lossy(data).into_owned();
    let mut lines: Vec<&str> = text.lines().collect();
    if lines.is_empty() {
        return;
    }
    let i = rng.random_range(0..lines.len());
    match rng.random_range(0..3) {
        0 => {
            let l = lines[i];
            lines.insert(rng.random_range(0..=lines.len()), l);
        }
        1 => {
            lines.remove(i);
        }
        _ => {
            let j = rng.random_range(0..lines.len());
            lines.swap(i, j);
        }
    }
    *data = lines.join("\n").into_bytes();
}

/// Repeats the first element of an array many times (long polygons, many seeds, many states).
fn grow_array(rng: &mut impl Rng, data: &mut Vec<u8>) {
    let opens: Vec<usize> = (0..data.len()).filter(|&i| data[i] == b'[').collect();
    if opens.is_empty() {
        return;
    }
    let a = *pick(rng, &opens) + 1;
    // the first element: up to the first ',' or ']' at depth 0
    let mut depth = 0i32;
    let mut b = a;
    while b < data.len() {
        match data[b] {
            b'[' | b'{' => depth += 1,
            b']' | b'}' if depth == 0 => break,
            b']' | b'}' => depth -= 1,
            b',' if depth == 0 => break,
            _ => {}
        }
        b += 1;
    }
    if b == a || b >= data.len() {
        return;
    }
    let elem = data[a..b].to_vec();
    let times = *pick(rng, &[2usize, 10, 100, 3000]);
    let mut extra = Vec::with_capacity((elem.len() + 2) * times);
    for _ in 0..times {
        extra.extend_from_slice(&elem);
        extra.extend_from_slice(b", ");
    }
    data.splice(a..a, extra);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_same_seed_gives_the_same_input_and_inputs_differ() {
        let seed = "a = [1.5, 2]\nb = \"x\"\n[t]\nc = -3\n";
        let corpus = vec![seed.to_string()];
        let a: Vec<Vec<u8>> = (0..200).map(|i| mutate(7, i, seed, &corpus)).collect();
        let b: Vec<Vec<u8>> = (0..200).map(|i| mutate(7, i, seed, &corpus)).collect();
        assert_eq!(a, b);
        let mut distinct = a.clone();
        distinct.sort();
        distinct.dedup();
        assert!(distinct.len() > 150, "{}", distinct.len());
        assert!(
            a.iter()
                .any(|x| String::from_utf8_lossy(x).contains("1e308"))
        );
    }
}
