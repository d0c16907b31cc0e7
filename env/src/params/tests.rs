use super::*;

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Mode {
    Fast,
    Slow,
}

impl ParamType for Mode {
    type Domain = ();
    fn parse(text: &str, _: &()) -> Result<Self, BadValue> {
        choose(text, &[("fast", Mode::Fast), ("slow", Mode::Slow)])
    }
    fn value(&self) -> Value {
        Value::Name(match self {
            Mode::Fast => "fast",
            Mode::Slow => "slow",
        })
    }
    fn describe(_: &()) -> String {
        "fast|slow".into()
    }
}

crate::declare_params! {
    /// Inner settings.
    #[derive(Debug, Clone, PartialEq)]
    pub struct Inner {
        /// Shortest (s).
        #[param("lo", Reals::POSITIVE)]
        pub lo: f64 = 0.25,
        /// Longest (s).
        #[param("hi", Reals::POSITIVE)]
        pub hi: f64 = 2.0,
    }
    check(|s: &Inner| if s.lo > s.hi {
        Err(crate::input::Rejection::new("", format!("lo {} exceeds hi {}", s.lo, s.hi)))
    } else {
        Ok(())
    });
}

crate::declare_params! {
    /// Outer settings.
    #[derive(Debug, Clone, PartialEq)]
    pub struct Outer {
        /// Tries per call,
        /// on two lines.
        #[param("k", 1..=100)]
        pub tries: usize = 5,
        /// The inner ones.
        #[params]
        pub inner: Inner,
        /// A flag.
        #[param("on")]
        pub on: bool = false,
        /// A mode.
        #[param("mode")]
        pub mode: Mode = Mode::Fast,
        /// A weight.
        #[param("w", Reals::closed(0.0, 1.0))]
        pub w: f64 = 1.0,
        /// State, not listed.
        pub count: u32 = 3,
    }
}

#[test]
fn defaults_listing_and_order_come_from_the_declaration() {
    let o = Outer::default();
    assert_eq!(
        (o.tries, o.inner.lo, o.inner.hi, o.on, o.mode, o.w, o.count),
        (5, 0.25, 2.0, false, Mode::Fast, 1.0, 3)
    );
    let names: Vec<String> = o
        .params()
        .into_iter()
        .map(|p| p.name.into_owned())
        .collect();
    assert_eq!(names, ["k", "lo", "hi", "on", "mode", "w"]);
    let k = &o.params()[0];
    assert_eq!(k.help, "Tries per call, on two lines.");
    assert_eq!(k.range, "[1, 100]");
    assert_eq!(k.value, Value::Whole(5));
    assert_eq!(o.params()[1].range, "> 0");
    assert_eq!(o.params()[5].range, "[0, 1]");
    // every listed default parses back to itself
    let mut again = Outer::default();
    for p in o.params() {
        again.set_param(&p.name, &p.value.to_string()).unwrap();
    }
    assert_eq!(again, o);
}

#[test]
fn typed_setters_parse_and_validate() {
    let mut o = Outer::default();
    for (k, v) in [
        ("k", "7"),
        ("lo", "0.5"),
        ("on", "true"),
        ("mode", "slow"),
        ("w", "0"),
    ] {
        o.set_param(k, v).unwrap();
    }
    assert_eq!(
        (o.tries, o.inner.lo, o.on, o.mode, o.w),
        (7, 0.5, true, Mode::Slow, 0.0)
    );
    o.set_param("k", "9.0").unwrap();
    assert_eq!(o.tries, 9, "a whole number written as a real");
    o.set_param("on", "0").unwrap();
    assert!(!o.on);
    for (k, v, why) in [
        ("k", "0", "must be in [1, 100]"),
        ("k", "2.5", "not a whole number"),
        ("k", "many", "not a whole number"),
        ("lo", "0", "must be in > 0"),
        ("lo", "nan", "must be in"),
        ("lo", "inf", "must be in"),
        ("w", "1.5", "must be in [0, 1]"),
        ("w", "x", "not a number"),
        ("on", "maybe", "not one of"),
        ("mode", "medium", "not one of fast, slow"),
    ] {
        match o.set_param(k, v) {
            Err(ParamError::BadValue(r)) => assert!(r.to_string().contains(why), "{k}={v}: {r}"),
            other => panic!("{k}={v}: {other:?}"),
        }
    }
    assert_eq!(
        o.set_param("count", "1"),
        Err(ParamError::Unknown("count".into()))
    );
}

#[test]
fn apply_names_the_source_the_field_and_the_reason() {
    let mut o = Outer::default();
    apply(
        "x.toml",
        "thing",
        &mut o,
        &owned(&[("k", "3"), ("hi", "4")]),
    )
    .unwrap();
    assert_eq!((o.tries, o.inner.hi), (3, 4.0));
    let e = apply("x.toml", "thing", &mut o, &owned(&[("kk", "3")])).unwrap_err();
    assert_eq!((e.file.as_str(), e.field.as_str()), ("x.toml", "param.kk"));
    assert!(
        e.reason
            .contains("thing has no parameter \"kk\" (known: k, lo, hi, on, mode, w)"),
        "{e}"
    );
    let e = apply("<command line>", "thing", &mut o, &owned(&[("w", "2")])).unwrap_err();
    assert_eq!(e.field, "param.w");
    let e = apply(
        "<command line>",
        "thing",
        &mut Outer::default(),
        &owned(&[("lo", "3")]),
    )
    .unwrap_err();
    assert_eq!(e.field, "param");
    assert!(e.reason.contains("thing: lo 3 exceeds hi 2"), "{e}");
}

#[test]
fn two_sets_act_as_one() {
    let (mut a, mut b) = (Inner::default(), Outer::default());
    apply(
        "s",
        "t",
        &mut Both(&mut a, &mut b),
        &owned(&[("lo", "1"), ("k", "2")]),
    )
    .unwrap();
    assert_eq!(
        (a.lo, b.inner.lo, b.tries),
        (1.0, 0.25, 2),
        "a key goes to the first set that has it"
    );
    let e = apply("s", "t", &mut Both(&mut a, &mut b), &owned(&[("z", "1")])).unwrap_err();
    assert!(e.reason.contains("(known: lo, hi, k, lo, hi"), "{e}");
    let fresh = Outer::default().params();
    assert_eq!(changed(&b.params(), &fresh), ["k=2"]);
}

#[test]
fn the_one_splitter() {
    assert_eq!(
        split_assignment("x", " k = 7 ").unwrap(),
        ("k".to_string(), "7".to_string())
    );
    assert_eq!(split_assignment("x", "metric=a=b").unwrap().1, "a=b");
    for bad in ["k7", "=7", " =7"] {
        let e = split_assignment("<command line>", bad).unwrap_err();
        assert_eq!(
            (e.file.as_str(), e.field.as_str()),
            ("<command line>", "param")
        );
        assert!(e.reason.contains("is not key=value"), "{e}");
    }
    assert_eq!(
        split_all("x", &["a=1".into(), "b=2".into()]).unwrap().len(),
        2
    );
}
