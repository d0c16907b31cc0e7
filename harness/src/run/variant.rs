//! Named parameter variants: `goal-zoom-rrt{k=5}` is the planner `goal-zoom-rrt` with `k = 5`.
//!
//! The label grammar is `NAME` or `NAME{KEY=VALUE, KEY=VALUE, ...}` where NAME and KEY are made
//! of letters, digits, `_` and `-`, and VALUE is a TOML value (integer, float, boolean or
//! quoted string). Labels are canonical: keys sorted, no spaces, so the same variant always
//! has the same label.

use std::collections::BTreeMap;
use std::fmt;

use magbench_env::input::Rejection;

/// A parameter value.
#[derive(Debug, Clone, PartialEq)]
pub enum ParamValue {
    /// An integer.
    Int(i64),
    /// A float.
    Float(f64),
    /// A boolean.
    Bool(bool),
    /// A string.
    Str(String),
}

impl fmt::Display for ParamValue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ParamValue::Int(v) => write!(f, "{v}"),
            ParamValue::Float(v) => {
                if v.fract() == 0.0 && v.abs() < 1e15 {
                    write!(f, "{v:.1}")
                } else {
                    write!(f, "{v}")
                }
            }
            ParamValue::Bool(v) => write!(f, "{v}"),
            ParamValue::Str(s) => write!(f, "{s}"),
        }
    }
}

impl ParamValue {
    /// From a TOML value; arrays, tables and dates are not parameters. A refusal's field is
    /// empty: the caller knows where the value stands.
    pub fn from_toml(v: &toml::Value) -> Result<Self, Rejection> {
        Ok(match v {
            toml::Value::Integer(i) => ParamValue::Int(*i),
            toml::Value::Float(x) if x.is_finite() => ParamValue::Float(*x),
            toml::Value::Float(x) => {
                return Err(Rejection::new("", format!("{x} is not a finite number")));
            }
            toml::Value::Boolean(b) => ParamValue::Bool(*b),
            toml::Value::String(s) => ParamValue::Str(s.clone()),
            other => {
                return Err(Rejection::new(
                    "",
                    format!(
                        "a parameter must be a number, boolean or string, not {}",
                        other.type_str()
                    ),
                ));
            }
        })
    }

    /// The value as a number, if it is one.
    pub fn as_f64(&self) -> Option<f64> {
        match self {
            ParamValue::Int(i) => Some(*i as f64),
            ParamValue::Float(x) => Some(*x),
            _ => None,
        }
    }

    fn label_text(&self) -> String {
        match self {
            ParamValue::Str(s) if !is_word(s) => format!("{s:?}"),
            other => other.to_string(),
        }
    }
}

/// A named component (planner or tracker) with parameter overrides.
#[derive(Debug, Clone, PartialEq)]
pub struct Variant {
    /// The registry name, e.g. `goal-zoom-rrt`.
    pub name: String,
    /// Parameter overrides (the component's defaults apply to the rest).
    pub params: BTreeMap<String, ParamValue>,
}

fn is_word(s: &str) -> bool {
    !s.is_empty()
        && s.chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-' || c == '.')
}

impl Variant {
    /// A variant without overrides.
    pub fn plain(name: &str) -> Self {
        Variant {
            name: name.to_string(),
            params: BTreeMap::new(),
        }
    }

    /// The canonical label: `name` or `name{a=1,b=0.5}` (keys sorted).
    pub fn label(&self) -> String {
        if self.params.is_empty() {
            return self.name.clone();
        }
        format!("{}{{{}}}", self.name, self.params_text())
    }

    /// The parameters as `a=1,b=0.5` (empty without overrides).
    pub fn params_text(&self) -> String {
        self.params
            .iter()
            .map(|(k, v)| format!("{k}={}", v.label_text()))
            .collect::<Vec<_>>()
            .join(",")
    }

    /// The parameters as `(key, value)` strings, the form of `--param key=value`.
    pub fn params_as_strings(&self) -> Vec<(String, String)> {
        self.params
            .iter()
            .map(|(k, v)| (k.clone(), v.to_string()))
            .collect()
    }

    /// Parses a label such as `goal-zoom-rrt{k=5, goal_bias=0.05}`. A refusal's field is
    /// empty (the caller knows where the label stands); its reason quotes the label.
    pub fn parse(label: &str) -> Result<Self, Rejection> {
        let label = label.trim();
        let refuse = |reason: String| Rejection::new("", format!("{label:?}: {reason}"));
        let (name, rest) = match label.find('{') {
            Some(i) => (&label[..i], Some(&label[i..])),
            None => (label, None),
        };
        let name = name.trim();
        // a plugin family's names have a prefix: `ompl:rrt`
        let plain = name
            .split_once(':')
            .map_or(name, |(family, n)| if is_word(family) { n } else { "" });
        if !is_word(plain) {
            return Err(refuse(
                "a name is letters, digits, '_' and '-' (with a family prefix such as `ompl:`), optionally followed by {key=value, ...}".into(),
            ));
        }
        let mut params = BTreeMap::new();
        if let Some(rest) = rest {
            let inner = rest
                .strip_prefix('{')
                .and_then(|r| r.strip_suffix('}'))
                .ok_or_else(|| refuse("parameters must be one {...} group at the end".into()))?;
            for part in split_top_level(inner) {
                let part = part.trim();
                if part.is_empty() {
                    continue;
                }
                let (k, v) = part
                    .split_once('=')
                    .ok_or_else(|| refuse(format!("{part:?} is not key=value")))?;
                let k = k.trim();
                if !is_word(k) {
                    return Err(refuse(format!("{k:?} is not a parameter name")));
                }
                let doc: toml::Table =
                    toml::from_str(&format!("v = {}", v.trim())).map_err(|_| {
                        refuse(format!(
                            "{k} = {} is not a number, boolean or quoted string",
                            v.trim()
                        ))
                    })?;
                let value = ParamValue::from_toml(&doc["v"])
                    .map_err(|e| refuse(format!("{k}: {}", e.reason)))?;
                if params.insert(k.to_string(), value).is_some() {
                    return Err(refuse(format!("parameter {k} given twice")));
                }
            }
        }
        Ok(Variant {
            name: name.to_string(),
            params,
        })
    }
}

/// Splits on commas outside quotes.
fn split_top_level(s: &str) -> Vec<&str> {
    let mut out = vec![];
    let (mut start, mut quote) = (0, None);
    for (i, c) in s.char_indices() {
        match (c, quote) {
            ('"' | '\'', None) => quote = Some(c),
            (q, Some(open)) if q == open => quote = None,
            (',', None) => {
                out.push(&s[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    out.push(&s[start..]);
    out
}

impl fmt::Display for Variant {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.label())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_and_canonicalises_labels() {
        let v = Variant::parse(" goal-zoom-rrt{ k = 5 , goal_bias=0.05}").unwrap();
        assert_eq!(v.name, "goal-zoom-rrt");
        assert_eq!(v.params["k"], ParamValue::Int(5));
        assert_eq!(v.params["goal_bias"], ParamValue::Float(0.05));
        assert_eq!(v.label(), "goal-zoom-rrt{goal_bias=0.05,k=5}");
        assert_eq!(Variant::parse(&v.label()).unwrap(), v);
        assert_eq!(Variant::parse("sst").unwrap().label(), "sst");
        let s = Variant::parse(r#"rrt-star{metric="com, sum", range=2.0, fast=true}"#).unwrap();
        assert_eq!(s.params["metric"], ParamValue::Str("com, sum".into()));
        assert_eq!(
            s.label(),
            r#"rrt-star{fast=true,metric="com, sum",range=2.0}"#
        );
        assert_eq!(Variant::parse(&s.label()).unwrap(), s);
    }

    #[test]
    fn rejects_bad_labels() {
        for bad in [
            "",
            "a b",
            "x{k}",
            "x{k=}",
            "x{k=5",
            "x{k=5}{j=1}",
            "x{k=1,k=2}",
            "x{k=nan}",
            "x{k=[1]}",
        ] {
            assert!(Variant::parse(bad).is_err(), "{bad:?} accepted");
        }
    }
}
