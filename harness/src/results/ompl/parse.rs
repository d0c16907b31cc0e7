//! A strict reader of OMPL's benchmark log format, following the grammar in OMPL's
//! documentation ("The benchmark logfile format"):
//!
//! ```text
//! logfile      ::= preamble planners_data
//! preamble     ::= [version] experiment [exp_property_count exp_properties] hostname date
//!                  setup [cpuinfo] random_seed time_limit memory_limit [num_runs]
//!                  total_time [num_enums enums] num_planners
//! planner_data ::= planner_name EOL int " common properties" EOL planner_properties
//!                  int " properties for each run" EOL run_properties
//!                  int " runs" EOL run_measurements
//!                  [int " progress properties for each run" EOL progress_properties
//!                   int " runs" EOL progress_measurements] "." EOL
//! run_measurement ::= (data "; ")*        progress_measurement ::= ((data ",")* ";")*
//! data         ::= num | "inf" | "nan" | ""
//! ```
//!
//! Property types are `BOOLEAN`, `INTEGER`, `REAL` and (as OMPL itself writes for `status`)
//! `ENUM`. Every value is checked against its type. Used by the tests as a second, independent
//! check of `ompl.log` next to OMPL's own `ompl_benchmark_statistics.py`.

/// A parsed log.
#[derive(Debug, Clone, PartialEq)]
pub struct Log {
    /// `(library, version)` from the optional first line.
    pub version: Option<(String, String)>,
    /// Experiment name.
    pub experiment: String,
    /// Experiment properties: `(name, type, value)`.
    pub properties: Vec<(String, String, String)>,
    /// Host.
    pub host: String,
    /// Start date.
    pub date: String,
    /// Setup text.
    pub setup: String,
    /// CPU information.
    pub cpuinfo: Option<String>,
    /// Random seed.
    pub seed: i64,
    /// Time limit per run (s).
    pub time_limit: f64,
    /// Memory limit per run (MB).
    pub memory_limit: f64,
    /// Runs per planner.
    pub runs_per_planner: Option<i64>,
    /// Total time (s).
    pub total_time: f64,
    /// Enum types: name and value descriptions.
    pub enums: Vec<(String, Vec<String>)>,
    /// Planner configurations.
    pub planners: Vec<PlannerData>,
}

/// One planner configuration's data.
#[derive(Debug, Clone, PartialEq)]
pub struct PlannerData {
    /// Name, e.g. `control_goal-zoom-rrt{k=5}`.
    pub name: String,
    /// Common properties `(name, value)`.
    pub common: Vec<(String, String)>,
    /// Run property names (with spaces) and types.
    pub properties: Vec<(String, String)>,
    /// Per run, one value per property (`None` for empty, `inf` or `nan`).
    pub runs: Vec<Vec<Option<String>>>,
    /// Progress property names and types.
    pub progress_properties: Vec<(String, String)>,
    /// Per run, its samples, each one value per progress property.
    pub progress: Vec<Vec<Vec<Option<String>>>>,
}

/// Why a log was refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum LogError {
    /// The text is empty.
    #[error("empty log")]
    Empty,
    /// The last line has no newline.
    #[error("the log does not end with a newline")]
    NoFinalNewline,
    /// Line `line` (1-based) breaks the grammar.
    #[error("line {line}: {reason}")]
    Line {
        /// The line number, from 1.
        line: usize,
        /// What is wrong with it.
        reason: String,
    },
}

/// A value that does not fit its property's type.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
enum ValueError {
    /// `inf` or `nan` for a type other than `REAL`.
    #[error("{value} is not a {ty}")]
    NotFinite {
        /// The value.
        value: String,
        /// The property's type.
        ty: String,
    },
    /// Text that is not a value of the type.
    #[error("{value:?} is not a valid {ty}")]
    Invalid {
        /// The value.
        value: String,
        /// The property's type.
        ty: String,
    },
}

/// A property declaration that is not `name TYPE`.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
enum PropertyError {
    /// No space between name and type.
    #[error("{0:?} is not \"name TYPE\"")]
    NoType(String),
    /// An unknown type or an empty name.
    #[error("{0:?}: the type must be BOOLEAN, INTEGER, REAL or ENUM")]
    BadType(String),
}

struct Lines<'a> {
    lines: Vec<&'a str>,
    at: usize,
}

impl<'a> Lines<'a> {
    fn peek(&self) -> Option<&'a str> {
        self.lines.get(self.at).copied()
    }
    fn next(&mut self, what: &str) -> Result<&'a str, LogError> {
        let l = self.peek().ok_or_else(|| LogError::Line {
            line: self.at + 1,
            reason: format!("end of file, expected {what}"),
        })?;
        self.at += 1;
        Ok(l)
    }
    /// An error at the line last read.
    fn err(&self, msg: impl std::fmt::Display) -> LogError {
        LogError::Line {
            line: self.at,
            reason: msg.to_string(),
        }
    }
    /// A line `<int><suffix>`.
    fn count(&mut self, suffix: &str) -> Result<usize, LogError> {
        let l = self.next(suffix)?;
        let n = l
            .strip_suffix(suffix)
            .ok_or_else(|| self.err(format!("expected \"N{suffix}\", got {l:?}")))?;
        n.parse()
            .map_err(|_| self.err(format!("{n:?} is not a count")))
    }
    fn multiline(&mut self) -> Result<String, LogError> {
        let open = self.next("<<<|")?;
        if open != "<<<|" {
            return Err(self.err(format!("expected <<<|, got {open:?}")));
        }
        let mut text = String::new();
        loop {
            let l = self.next("|>>>")?;
            if l.starts_with("|>>>") {
                return Ok(text);
            }
            text += l;
            text.push('\n');
        }
    }
}

fn check_value(v: &str, ty: &str, enum_size: usize) -> Result<Option<String>, ValueError> {
    if v.is_empty() || v == "inf" || v == "nan" {
        if (v == "inf" || v == "nan") && ty != "REAL" {
            return Err(ValueError::NotFinite {
                value: v.to_string(),
                ty: ty.to_string(),
            });
        }
        return Ok(None);
    }
    let ok = match ty {
        "BOOLEAN" => v == "0" || v == "1",
        "INTEGER" => v.parse::<i64>().is_ok(),
        "REAL" => v.parse::<f64>().is_ok_and(|x| x.is_finite()),
        "ENUM" => v.parse::<usize>().is_ok_and(|x| x < enum_size),
        _ => false,
    };
    if ok {
        Ok(Some(v.to_string()))
    } else {
        Err(ValueError::Invalid {
            value: v.to_string(),
            ty: ty.to_string(),
        })
    }
}

fn property(l: &str) -> Result<(String, String), PropertyError> {
    let (name, ty) = l
        .rsplit_once(' ')
        .ok_or_else(|| PropertyError::NoType(l.to_string()))?;
    if !["BOOLEAN", "INTEGER", "REAL", "ENUM"].contains(&ty) || name.trim().is_empty() {
        return Err(PropertyError::BadType(l.to_string()));
    }
    Ok((name.to_string(), ty.to_string()))
}

/// Parses a whole log.
pub fn parse(text: &str) -> Result<Log, LogError> {
    if !text.ends_with('\n') {
        return Err(LogError::NoFinalNewline);
    }
    let mut l = Lines {
        lines: text.lines().collect(),
        at: 0,
    };
    let mut version = None;
    let first = l.peek().ok_or(LogError::Empty)?;
    let toks: Vec<&str> = first.split(' ').collect();
    if toks.len() == 3 && toks[1] == "version" {
        version = Some((toks[0].to_string(), toks[2].to_string()));
        l.at += 1;
    }
    let exp = l.next("Experiment")?;
    let experiment = exp
        .strip_prefix("Experiment ")
        .filter(|n| !n.contains(char::is_whitespace) && !n.is_empty())
        .ok_or_else(|| l.err(format!("expected \"Experiment NAME\", got {exp:?}")))?;
    let mut properties = vec![];
    if l.peek()
        .is_some_and(|s| s.ends_with(" experiment properties"))
    {
        let n = l.count(" experiment properties")?;
        for _ in 0..n {
            let p = l.next("an experiment property")?;
            let (lhs, value) = p
                .split_once(" = ")
                .ok_or_else(|| l.err(format!("{p:?} is not \"name TYPE = value\"")))?;
            let (name, ty) = lhs
                .rsplit_once(' ')
                .ok_or_else(|| l.err(format!("{lhs:?} has no type")))?;
            properties.push((name.to_string(), ty.to_string(), value.to_string()));
        }
    }
    let host = l.next("Running on")?;
    let host = host
        .strip_prefix("Running on ")
        .filter(|h| !h.contains(char::is_whitespace))
        .ok_or_else(|| l.err("expected \"Running on HOST\""))?
        .to_string();
    let date = l
        .next("Starting at")?
        .strip_prefix("Starting at ")
        .ok_or_else(|| l.err("expected \"Starting at DATE\""))?
        .to_string();
    let setup = l.multiline()?;
    let cpuinfo = if l.peek() == Some("<<<|") {
        Some(l.multiline()?)
    } else {
        None
    };
    let seed = l.next("the random seed")?;
    let seed = seed
        .strip_suffix(" is the random seed")
        .and_then(|s| s.parse().ok())
        .ok_or_else(|| l.err(format!("expected \"INT is the random seed\", got {seed:?}")))?;
    let float_line = |l: &mut Lines, suffix: &str| -> Result<f64, LogError> {
        let s = l.next(suffix)?;
        s.strip_suffix(suffix)
            .and_then(|x| x.parse().ok())
            .ok_or_else(|| l.err(format!("expected \"FLOAT{suffix}\", got {s:?}")))
    };
    let time_limit = float_line(&mut l, " seconds per run")?;
    let memory_limit = float_line(&mut l, " MB per run")?;
    let runs_per_planner = if l.peek().is_some_and(|s| s.ends_with(" runs per planner")) {
        Some(l.count(" runs per planner")? as i64)
    } else {
        None
    };
    let total_time = float_line(&mut l, " seconds spent to collect the data")?;
    let mut enums = vec![];
    if l.peek().is_some_and(|s| s.ends_with(" enum type")) {
        let n = l.count(" enum type")?;
        for _ in 0..n {
            let e = l.next("an enum")?;
            let mut parts = e.split('|');
            let name = parts.next().unwrap_or_default().to_string();
            let values: Vec<String> = parts.map(str::to_string).collect();
            if values.is_empty() {
                return Err(l.err(format!("enum {name:?} has no values")));
            }
            enums.push((name, values));
        }
    }
    let enum_size = enums
        .iter()
        .find(|(n, _)| n == "status")
        .map(|(_, v)| v.len())
        .unwrap_or(0);
    let np = l.count(" planners")?;
    let mut planners = vec![];
    for _ in 0..np {
        let name = l.next("a planner name")?.to_string();
        let nc = l.count(" common properties")?;
        let mut common = vec![];
        for _ in 0..nc {
            let c = l.next("a common property")?;
            let (k, v) = c
                .split_once(" = ")
                .ok_or_else(|| l.err(format!("{c:?} is not \"name = value\"")))?;
            common.push((k.to_string(), v.to_string()));
        }
        let npr = l.count(" properties for each run")?;
        let mut props = vec![];
        for _ in 0..npr {
            let p = l.next("a run property")?;
            props.push(property(p).map_err(|e| l.err(e))?);
        }
        let nr = l.count(" runs")?;
        let mut runs = vec![];
        for _ in 0..nr {
            let line = l.next("a run")?;
            let body = line
                .strip_suffix("; ")
                .or_else(|| (line.is_empty() && props.is_empty()).then_some(""))
                .ok_or_else(|| l.err("a run line must end with \"; \""))?;
            let values: Vec<&str> = if props.is_empty() {
                vec![]
            } else {
                body.split("; ").collect()
            };
            if values.len() != props.len() {
                return Err(l.err(format!(
                    "{} values for {} properties",
                    values.len(),
                    props.len()
                )));
            }
            let checked = values
                .iter()
                .zip(&props)
                .map(|(v, (n, t))| {
                    check_value(v, t, enum_size).map_err(|e| l.err(format!("{n}: {e}")))
                })
                .collect::<Result<Vec<_>, _>>()?;
            runs.push(checked);
        }
        let mut progress_properties = vec![];
        let mut progress = vec![];
        if l.peek() != Some(".") {
            let npp = l.count(" progress properties for each run")?;
            for _ in 0..npp {
                let p = l.next("a progress property")?;
                progress_properties.push(property(p).map_err(|e| l.err(e))?);
            }
            let nrp = l.count(" runs")?;
            if nrp != nr {
                return Err(l.err(format!("progress for {nrp} runs, but {nr} runs")));
            }
            for _ in 0..nrp {
                let line = l.next("progress samples")?;
                if !line.is_empty() && !line.ends_with(';') {
                    return Err(l.err("progress samples must end with ';'"));
                }
                let mut samples = vec![];
                for s in line.split(';').filter(|s| !s.is_empty()) {
                    let body = s
                        .strip_suffix(',')
                        .ok_or_else(|| l.err(format!("sample {s:?} must end with ','")))?;
                    let values: Vec<&str> = body.split(',').collect();
                    if values.len() != progress_properties.len() {
                        return Err(l.err(format!(
                            "a sample has {} values for {} properties",
                            values.len(),
                            progress_properties.len()
                        )));
                    }
                    samples.push(
                        values
                            .iter()
                            .zip(&progress_properties)
                            .map(|(v, (_, t))| check_value(v, t, enum_size))
                            .collect::<Result<Vec<_>, _>>()
                            .map_err(|e| l.err(e))?,
                    );
                }
                progress.push(samples);
            }
        }
        let dot = l.next("\".\"")?;
        if dot != "." {
            return Err(l.err(format!(
                "expected \".\" closing planner {name:?}, got {dot:?}"
            )));
        }
        planners.push(PlannerData {
            name,
            common,
            properties: props,
            runs,
            progress_properties,
            progress,
        });
    }
    if let Some(extra) = l.peek() {
        return Err(LogError::Line {
            line: l.at + 1,
            reason: format!("unexpected text after the last planner: {extra:?}"),
        });
    }
    Ok(Log {
        version,
        experiment: experiment.to_string(),
        properties,
        host,
        date,
        setup,
        cpuinfo,
        seed,
        time_limit,
        memory_limit,
        runs_per_planner,
        total_time,
        enums,
        planners,
    })
}
