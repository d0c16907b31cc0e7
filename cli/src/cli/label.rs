//! Planners and trackers named on the command line: a registry name, or a label as experiment
//! files and reports write it, `name{key=value,…}`, read by the experiment files' own parser
//! ([`Variant::parse`], with its errors). The repeatable `key=value` options (`--param`,
//! `--planner-param`) add to the label's parameters; a key given in both is refused.

use magbench_env::params::split_all;

use crate::Error;
use crate::run::Variant;

/// The component `label` of option `option` (e.g. `--planner`) with the `key=value` texts
/// `params` of option `param_option` (e.g. `--param`) merged into its parameters: its registry
/// name and every parameter as `(key, value)`, the label's first. Exit 2 naming the option on
/// a bad label, a bad `key=value`, or a key both in the label and in an option.
pub fn named(
    option: &str,
    label: &str,
    param_option: &str,
    params: &[String],
) -> Result<(String, Vec<(String, String)>), Error> {
    let v = Variant::parse(label).map_err(|r| Error::rejected(option, r))?;
    let mut all = v.params_as_strings();
    for (k, value) in split_all("<command line>", params)? {
        if v.params.contains_key(&k) {
            return Err(Error::arg(
                param_option,
                format!(
                    "{k} is given both in {option} {label} and in {param_option} {k}={value}; give it once"
                ),
            ));
        }
        all.push((k, value));
    }
    Ok((v.name, all))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_label_and_options_merge() {
        let (name, params) = named(
            "--planner",
            "goal-zoom-rrt{k=5, aim=true}",
            "--param",
            &["guide=true".into()],
        )
        .unwrap();
        assert_eq!(name, "goal-zoom-rrt");
        let kv = |k: &str, v: &str| (k.to_string(), v.to_string());
        assert_eq!(
            params,
            vec![kv("aim", "true"), kv("k", "5"), kv("guide", "true")]
        );
        let e = named("--planner", "sst{k=5}", "--param", &["k=6".into()]).unwrap_err();
        assert_eq!(e.exit_code(), 2);
        assert!(e.to_string().contains("--param: k is given both"), "{e}");
        let e = named("--tracker", "obc{", "--param", &[]).unwrap_err();
        assert!(e.to_string().contains("--tracker: \"obc{\""), "{e}");
    }
}
