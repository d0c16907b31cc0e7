//! The compact form of a replay page's data. The page keeps the small fields (title, scene,
//! events, metrics, the plans' and trees' headers) as JSON and the bulk numbers as one string:
//! integer columns, written as zig-zag varints, raw-deflated and base64-encoded. The player
//! inflates it with the browser's `DecompressionStream` and rebuilds [`ReplayData`]'s arrays.
//!
//! A column is its length, then its values; a *delta* column stores each value minus the one
//! before it (the first minus 0), which makes slowly changing series small. The columns, in
//! order (`n` agents, `F` frames):
//!
//! 1. `t` in ms (delta), `leg` (delta), `plan` (delta);
//! 2. per agent: `truth` x, y (delta);
//! 3. one value: the agents with observations (0 or `n`); per such agent: a 0/1 column of the
//!    frames with a detection, then x and y of those detections minus the truth;
//! 4. the field: angle, elevation (0.1°), gradient x, y (0.1 mT/m), each delta;
//! 5. per plan: one value, its paths; per path: x, y (delta);
//! 6. per tree: the edges' first points x (delta, the edges are sorted by it) and y, and the
//!    offsets to their second points x, y, in [`super::data::TREE_SCALE`] units.

use std::io::Write;

use base64::Engine;
use serde_json::Value;

use super::data::{FieldFrame, ReplayData};

/// A column writer: zig-zag varints into one byte buffer.
#[derive(Default)]
struct Columns(Vec<u8>);

impl Columns {
    fn num(&mut self, v: i64) {
        let mut u = ((v << 1) ^ (v >> 63)) as u64;
        while u >= 0x80 {
            self.0.push((u as u8 & 0x7f) | 0x80);
            u >>= 7;
        }
        self.0.push(u as u8);
    }

    fn values(&mut self, xs: &[i64]) {
        self.num(xs.len() as i64);
        xs.iter().for_each(|&x| self.num(x));
    }

    fn deltas(&mut self, xs: &[i64]) {
        self.num(xs.len() as i64);
        let mut last = 0;
        for &x in xs {
            self.num(x - last);
            last = x;
        }
    }

    /// Every other value of `flat`, from `from`.
    fn axis(flat: &[i32], from: usize) -> Vec<i64> {
        flat.iter()
            .skip(from)
            .step_by(2)
            .map(|&v| v as i64)
            .collect()
    }
}

/// The bulk numbers of `d` as the columns above, deflated and base64-encoded.
pub fn pack(d: &ReplayData) -> String {
    let mut c = Columns::default();
    let tenths = |x: f64| (x * 10.0).round() as i64;
    c.deltas(
        &d.t.iter()
            .map(|&t| (t * 1000.0).round() as i64)
            .collect::<Vec<_>>(),
    );
    c.deltas(&d.leg.iter().map(|&v| v as i64).collect::<Vec<_>>());
    c.deltas(&d.plan.iter().map(|&v| v as i64).collect::<Vec<_>>());
    for a in &d.truth {
        c.deltas(&Columns::axis(a, 0));
        c.deltas(&Columns::axis(a, 1));
    }
    c.num(d.obs.len() as i64);
    for (o, a) in d.obs.iter().zip(&d.truth) {
        // each frame's detection minus the truth, or None for a missed one
        let off: Vec<Option<[i64; 2]>> = o
            .chunks_exact(2)
            .zip(a.chunks_exact(2))
            .map(|(o, a)| Some([o[0]? as i64 - a[0] as i64, o[1]? as i64 - a[1] as i64]))
            .collect();
        c.values(
            &off.iter()
                .map(|d| i64::from(d.is_some()))
                .collect::<Vec<_>>(),
        );
        for axis in 0..2 {
            c.values(&off.iter().flatten().map(|d| d[axis]).collect::<Vec<_>>());
        }
    }
    let field: [fn(&FieldFrame) -> f64; 4] = [|f| f.0, |f| f.1, |f| f.2, |f| f.3];
    for part in field {
        c.deltas(&d.field.iter().map(|f| tenths(part(f))).collect::<Vec<_>>());
    }
    for p in &d.plans {
        c.num(p.paths.len() as i64);
        for path in &p.paths {
            c.deltas(&Columns::axis(path, 0));
            c.deltas(&Columns::axis(path, 1));
        }
    }
    for t in &d.trees {
        let e = |i: usize| -> Vec<i64> {
            t.edges
                .chunks_exact(4)
                .map(|q| match i {
                    0 | 1 => q[i] as i64,
                    _ => (q[i] - q[i - 2]) as i64,
                })
                .collect()
        };
        c.deltas(&e(0));
        c.values(&e(1));
        c.values(&e(2));
        c.values(&e(3));
    }
    let mut z = flate2::write::DeflateEncoder::new(Vec::new(), flate2::Compression::best());
    z.write_all(&c.0).expect("deflate into memory");
    let bytes = z.finish().expect("deflate into memory");
    base64::engine::general_purpose::STANDARD.encode(bytes)
}

/// The JSON a page holds for `d`: its small fields, and its bulk numbers in `packed`.
pub fn page_json(d: &ReplayData) -> Value {
    let mut v = serde_json::to_value(d).expect("replay data serializes");
    let o = v.as_object_mut().expect("an object");
    for k in ["t", "leg", "plan", "truth", "obs", "field"] {
        o.remove(k);
    }
    for p in o["plans"].as_array_mut().into_iter().flatten() {
        p.as_object_mut().expect("a plan").remove("paths");
    }
    for t in o["trees"].as_array_mut().into_iter().flatten() {
        t.as_object_mut().expect("a tree").remove("edges");
    }
    o.insert("packed".into(), Value::String(pack(d)));
    v
}

#[cfg(test)]
mod tests {
    use std::io::Read;

    use super::*;
    use crate::replay::data::{ReplayPlan, ReplayTree};

    /// The columns of a packed string, read as the player reads them.
    fn unpack(s: &str) -> Vec<u8> {
        let bytes = base64::engine::general_purpose::STANDARD.decode(s).unwrap();
        let mut out = vec![];
        flate2::read::DeflateDecoder::new(&bytes[..])
            .read_to_end(&mut out)
            .unwrap();
        out
    }

    struct Reader<'a>(&'a [u8], usize);

    impl Reader<'_> {
        fn num(&mut self) -> i64 {
            let (mut u, mut shift) = (0u64, 0);
            loop {
                let b = self.0[self.1];
                self.1 += 1;
                u |= ((b & 0x7f) as u64) << shift;
                shift += 7;
                if b & 0x80 == 0 {
                    return (u >> 1) as i64 ^ -((u & 1) as i64);
                }
            }
        }
        fn col(&mut self, delta: bool) -> Vec<i64> {
            let n = self.num();
            let mut acc = 0;
            (0..n)
                .map(|_| {
                    let v = self.num();
                    acc = if delta { acc + v } else { v };
                    acc
                })
                .collect()
        }
    }

    fn sample() -> ReplayData {
        let s = magbench_env::Scenario::load("open-field").unwrap();
        let mut d = ReplayData::planned(
            &s,
            "t".into(),
            &[],
            &[],
            &magbench_env::PlanningModel::new(&s.physics),
        );
        d.t = vec![0.0, 0.033, 0.067];
        d.leg = vec![0, 0, 1];
        d.plan = vec![0, 0, 1];
        d.truth = vec![
            vec![100, 200, 101, 199, -5, 7],
            vec![0, 0, 3, 4, 1 << 20, -1],
        ];
        d.obs = vec![
            vec![Some(102), Some(198), None, None, Some(-4), Some(9)],
            vec![None, None, Some(1), Some(2), None, None],
        ];
        d.field = vec![
            FieldFrame(90.0, 0.0, 1.5, -2.3),
            FieldFrame(-179.9, 12.5, 0.0, 0.1),
            FieldFrame(0.1, 0.0, 0.0, 0.0),
        ];
        d.plans = vec![ReplayPlan {
            leg: 0,
            t0: 0.0,
            reason: "plan".into(),
            solved: true,
            paths: vec![vec![1, 2, 3, 4], vec![-1, -2]],
        }];
        d.trees = vec![ReplayTree {
            leg: 0,
            nodes: 3,
            edges: vec![1, 2, 3, 4, 5, 6, 7, -8],
        }];
        d
    }

    #[test]
    fn the_columns_give_back_every_number() {
        let d = sample();
        let bytes = unpack(&pack(&d));
        let mut r = Reader(&bytes, 0);
        assert_eq!(r.col(true), [0, 33, 67]);
        assert_eq!(r.col(true), [0, 0, 1]);
        assert_eq!(r.col(true), [0, 0, 1]);
        assert_eq!(r.col(true), [100, 101, -5]);
        assert_eq!(r.col(true), [200, 199, 7]);
        assert_eq!(r.col(true), [0, 3, 1 << 20]);
        assert_eq!(r.col(true), [0, 4, -1]);
        assert_eq!(r.num(), 2);
        assert_eq!(r.col(false), [1, 0, 1]);
        assert_eq!(r.col(false), [2, 1]);
        assert_eq!(r.col(false), [-2, 2]);
        assert_eq!(r.col(false), [0, 1, 0]);
        assert_eq!(r.col(false), [-2]);
        assert_eq!(r.col(false), [-2]);
        assert_eq!(r.col(true), [900, -1799, 1]);
        assert_eq!(r.col(true), [0, 125, 0]);
        assert_eq!(r.col(true), [15, 0, 0]);
        assert_eq!(r.col(true), [-23, 1, 0]);
        assert_eq!(r.num(), 2);
        assert_eq!(r.col(true), [1, 3]);
        assert_eq!(r.col(true), [2, 4]);
        assert_eq!(r.col(true), [-1]);
        assert_eq!(r.col(true), [-2]);
        assert_eq!(r.col(true), [1, 5]);
        assert_eq!(r.col(false), [2, 6]);
        assert_eq!(r.col(false), [2, 2]);
        assert_eq!(r.col(false), [2, -14]);
        assert_eq!(r.1, bytes.len(), "nothing left over");
    }

    #[test]
    fn the_page_json_holds_the_small_fields_and_the_packed_string() {
        let v = page_json(&sample());
        for k in ["t", "leg", "plan", "truth", "obs", "field"] {
            assert!(v.get(k).is_none(), "{k}");
        }
        assert!(v["plans"][0].get("paths").is_none());
        assert!(v["trees"][0].get("edges").is_none());
        assert_eq!(v["trees"][0]["nodes"], 3);
        assert_eq!(v["plans"][0]["reason"], "plan");
        assert!(v["packed"].as_str().unwrap().len() > 10);
        assert_eq!(v["scale"], 100.0);
    }
}
