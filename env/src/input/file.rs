//! The one loader of input files: read a regular file (bounded in size), parse TOML or JSON into
//! a serde type, and report every failure as an [`InputError`] naming the file, the field path
//! and the line. Unknown keys get the closest known key (see [`super::suggest`]).
//!
//! Scenario, experiment, rig, preset and plan files all load through here, so their messages
//! read alike: `FILE: FIELD: REASON (line N)`.

use std::io::Read;
use std::path::Path;

use serde::de::DeserializeOwned;

use crate::error::InputError;

/// Largest input file read (bytes). Scenario, experiment, rig and plan files are far smaller;
/// the bound keeps `/dev/zero` or a mistaken multi-gigabyte file from exhausting memory.
pub const MAX_INPUT_BYTES: u64 = 64 << 20;

/// Largest TOML input parsed (bytes): 4 MiB. The TOML parser takes about 80 bytes of memory per
/// byte of dense TOML (`magbench bench --dry-run` of a 62 MiB experiment file of one long array
/// peaked at 4.9 GB), so 4 MiB stays within the memory budget; the TOML formats' files
/// (scenario, experiment, rig, preset, suite) are a few KiB.
pub const MAX_TOML_BYTES: usize = 4 << 20;

/// Reads a regular text file of at most [`MAX_INPUT_BYTES`]; `file` names it in errors.
///
/// A FIFO, a socket or a device is refused before it is opened (reading one waits for a
/// writer, or never ends): inputs are files.
pub fn read_text(path: &Path, file: &str) -> Result<String, InputError> {
    read_text_at_most(path, file, MAX_INPUT_BYTES)
}

/// Reads a regular text file of at most `max` bytes (a format's own bound, below
/// [`MAX_INPUT_BYTES`]); `file` names it in errors.
pub fn read_text_at_most(path: &Path, file: &str, max: u64) -> Result<String, InputError> {
    let cannot = |e: std::io::Error| InputError::new(file, "", format!("cannot read: {e}"));
    let meta = std::fs::metadata(path).map_err(cannot)?;
    if !meta.is_file() {
        return Err(InputError::new(
            file,
            "",
            format!(
                "cannot read: {} is not a regular file; inputs are files (copy a stream to one first)",
                kind(&meta)
            ),
        ));
    }
    let f = std::fs::File::open(path).map_err(cannot)?;
    let mut text = String::new();
    f.take(max + 1).read_to_string(&mut text).map_err(cannot)?;
    if text.len() as u64 > max {
        return Err(InputError::new(
            file,
            "",
            format!(
                "cannot read: larger than {} KiB; is it the right file?",
                max >> 10
            ),
        ));
    }
    Ok(text)
}

/// What a non-regular file is, for a message.
fn kind(meta: &std::fs::Metadata) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        let t = meta.file_type();
        if t.is_fifo() {
            return "a FIFO (named pipe)";
        }
        if t.is_socket() {
            return "a socket";
        }
        if t.is_block_device() || t.is_char_device() {
            return "a device";
        }
    }
    if meta.is_dir() {
        "a directory"
    } else {
        "a special file"
    }
}

/// Parses JSON `text` into `T`; `file` names it in errors, which carry the field path
/// (`states[3][1]`) and the line.
pub fn parse_json<T: DeserializeOwned>(text: &str, file: &str) -> Result<T, InputError> {
    let mut de = serde_json::Deserializer::from_str(text);
    let value: T = serde_path_to_error::deserialize(&mut de).map_err(|e| {
        let path = e.path().to_string();
        let inner = e.into_inner();
        let field = if path == "." { String::new() } else { path };
        let msg = inner.to_string();
        // serde_json ends its messages with " at line L column C"
        let msg = match msg.rsplit_once(" at line ") {
            Some((m, at)) => format!(
                "{} (line {})",
                super::suggest::explain(m),
                at.split(' ').next().unwrap_or(at)
            ),
            None => super::suggest::explain(&msg),
        };
        InputError::new(file, field, msg)
    })?;
    de.end()
        .map_err(|e| InputError::new(file, "", format!("invalid JSON: {e}")))?;
    Ok(value)
}

/// Parses TOML `text` into `T`; `file` names it in errors, which carry the dotted field path
/// and the line of the offending value.
pub fn parse_toml<T: DeserializeOwned>(text: &str, file: &str) -> Result<T, InputError> {
    if text.len() > MAX_TOML_BYTES {
        return Err(InputError::new(
            file,
            "",
            format!(
                "larger than {} KiB, the most a TOML input may be (parsing takes about 80 bytes of memory per byte, within the 2 GiB memory budget); is it the right file?",
                MAX_TOML_BYTES >> 10
            ),
        ));
    }
    let de = toml::Deserializer::parse(text).map_err(|e| {
        InputError::new(
            file,
            "",
            format!(
                "invalid TOML: {}{}",
                e.message().trim(),
                at_line(text, e.span())
            ),
        )
    })?;
    let mut ignored = Vec::new();
    let mut note = |path: serde_ignored::Path| ignored.push(unindexed(&path.to_string()));
    let de = serde_ignored::Deserializer::new(de, &mut note);
    let parsed = serde_path_to_error::deserialize(de);
    parsed.map_err(|e| {
        let path = e.path().to_string();
        let inner = e.into_inner();
        let field = if path == "." { String::new() } else { path };
        let reason = format!(
            "{}{}{}",
            super::suggest::explain(inner.message().trim()),
            at_line(text, inner.span()),
            misspelt::<T>(text, &field, inner.message(), &ignored)
        );
        InputError::new(file, field, reason)
    })
}

/// ` (line N)` for the line of dotted `field` (`table.sub.key`) in TOML `text`: the key's line
/// inside its table, else the table's header, else nothing. For errors found after parsing
/// (a value out of range), whose serde span is gone.
pub fn field_line(text: &str, field: &str) -> String {
    let (table, key) = match field.rsplit_once('.') {
        Some((t, k)) => (t, k),
        None => ("", field),
    };
    let header = |l: &str| {
        let l = l.trim();
        l.starts_with('[')
            .then(|| l.trim_matches(|c| c == '[' || c == ']').trim().to_string())
    };
    let is_key = |l: &str| {
        l.trim_start()
            .strip_prefix(key)
            .is_some_and(|rest| rest.trim_start().starts_with('='))
    };
    let mut current = String::new();
    let mut table_line = None;
    for (n, l) in text.lines().enumerate() {
        if let Some(h) = header(l) {
            current = h;
            if current == table {
                table_line.get_or_insert(n + 1);
            }
            continue;
        }
        if current == table && !key.is_empty() && is_key(l) {
            return format!(" (line {})", n + 1);
        }
    }
    table_line
        .map(|n| format!(" (line {n})"))
        .unwrap_or_default()
}

/// A dotted key path without array indices (`legs[0].x` and `legs.0.x` are both `legs.x`).
fn unindexed(path: &str) -> String {
    path.split('.')
        .map(|p| p.split('[').next().unwrap_or(p))
        .filter(|p| !p.is_empty() && !p.chars().all(|c| c.is_ascii_digit()))
        .collect::<Vec<_>>()
        .join(".")
}

/// The key a probe writes into a table to learn its schema's fields (sorted first, so read
/// first).
const PROBE: &str = "__field_probe__";

/// The table of `doc` at a dotted path (`a.b[2].c`: indices step into arrays of tables).
fn table_at<'a>(doc: &'a mut toml::Table, path: &[&str]) -> Option<&'a mut toml::Table> {
    let mut t = doc;
    for part in path {
        let (key, index) = match part.split_once('[') {
            Some((k, i)) => (k, i.trim_end_matches(']').parse::<usize>().ok()),
            None => (*part, None),
        };
        let v = t.get_mut(key)?;
        t = match (v, index) {
            (toml::Value::Array(a), Some(i)) => a.get_mut(i)?.as_table_mut()?,
            (v, None) => v.as_table_mut()?,
            _ => return None,
        };
    }
    Some(t)
}

/// The fields `T` reads in the table of `doc` at `path`, as its own "unknown field" error
/// lists them when a probe key is written there; `None` when the table takes any key or the
/// probe is not what fails.
fn fields_of<T: DeserializeOwned>(doc: &toml::Table, path: &[&str]) -> Option<Vec<String>> {
    let mut probed = doc.clone();
    table_at(&mut probed, path)?.insert(PROBE.into(), toml::Value::Integer(0));
    let text = toml::to_string(&probed).ok()?;
    let e = toml::from_str::<T>(&text).err()?;
    let list = e
        .message()
        .strip_prefix(&format!("unknown field `{PROBE}`, "))?
        .to_string();
    Some(
        list.split('`')
            .skip(1)
            .step_by(2)
            .map(String::from)
            .collect(),
    )
}

/// For a `missing field `F`` error at `field`: a key written next to it that looks like a
/// misspelling of `F` (or of the table at `field` itself), as `; is `wrold` a misspelling of
/// `world`?`. A key the schema reads there is a field in its own right, not a candidate; where
/// the schema takes any key, only those it ignored (`ignored`, dotted paths without indices)
/// are.
fn misspelt<T: DeserializeOwned>(
    text: &str,
    field: &str,
    message: &str,
    ignored: &[String],
) -> String {
    let Some(missing) = message
        .strip_prefix("missing field `")
        .and_then(|r| r.split('`').next())
    else {
        return String::new();
    };
    let Ok(mut doc) = text.parse::<toml::Table>() else {
        return String::new();
    };
    let path: Vec<&str> = if field.is_empty() {
        vec![]
    } else {
        field.split('.').collect()
    };
    let mut tries = vec![(path.clone(), missing.to_string())];
    if let Some((last, parent)) = path.split_last() {
        let name = last.split('[').next().unwrap_or(last).to_string();
        tries.push((parent.to_vec(), name));
    }
    for (at, wanted) in tries {
        let prefix = unindexed(&at.join("."));
        let known = fields_of::<T>(&doc, &at);
        let candidate = |k: &&String| match &known {
            Some(fields) => !fields.contains(k),
            None => ignored.contains(&if prefix.is_empty() {
                k.to_string()
            } else {
                format!("{prefix}.{k}")
            }),
        };
        if let Some(t) = table_at(&mut doc, &at)
            && let Some(k) = super::suggest::did_you_mean(
                &wanted,
                t.keys().filter(candidate).map(String::as_str),
            )
        {
            return format!("; is `{k}` a misspelling of `{wanted}`?");
        }
    }
    String::new()
}

/// ` (line N)` for a byte span of `text`, or nothing without one.
fn at_line(text: &str, span: Option<std::ops::Range<usize>>) -> String {
    span.map(|s| {
        let upto = s.start.min(text.len());
        // a span inside a multi-byte character must not split it
        let upto = (0..=upto)
            .rev()
            .find(|&i| text.is_char_boundary(i))
            .unwrap_or(0);
        format!(" (line {})", text[..upto].matches('\n').count() + 1)
    })
    .unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, serde::Deserialize)]
    #[serde(deny_unknown_fields)]
    #[allow(dead_code)]
    struct T {
        a: f64,
        b: Option<Vec<u32>>,
    }

    #[test]
    fn toml_beyond_its_bound_is_refused_before_parsing() {
        let mut big = String::from("a = 1.0\nb = [");
        while big.len() <= MAX_TOML_BYTES {
            big.push_str("1,");
        }
        big.push_str("1]\n");
        let e = parse_toml::<T>(&big, "t.toml").unwrap_err();
        assert_eq!((e.file.as_str(), e.field.as_str()), ("t.toml", ""));
        assert!(e.reason.contains("larger than 4096 KiB"), "{e}");
        // one byte under the bound parses
        let ok = format!("a = 1.0\n#{}\n", "x".repeat(MAX_TOML_BYTES - 10));
        assert_eq!(ok.len(), MAX_TOML_BYTES);
        assert!(parse_toml::<T>(&ok, "t.toml").is_ok());
    }

    #[test]
    fn errors_name_the_field_and_the_line() {
        let e = parse_toml::<T>("a = 1.0\n\nb = [1, \"x\"]\n", "t.toml").unwrap_err();
        assert_eq!(e.file, "t.toml");
        assert_eq!(e.field, "b[1]");
        assert!(e.reason.ends_with("(line 3)"), "{e}");
        let e = parse_toml::<T>("a = 1.0\nc = 2\n", "t.toml").unwrap_err();
        assert!(
            e.reason.contains("unknown field") && e.reason.contains("line 2"),
            "{e}"
        );
        let e = parse_toml::<T>(
            "a = 1.0
bb = 2
",
            "t.toml",
        )
        .unwrap_err();
        assert!(e.reason.contains("did you mean `b`?"), "{e}");
        let e = parse_json::<T>("{\"a\": 1, \"b\": [1, -2]}", "t.json").unwrap_err();
        assert_eq!(e.field, "b[1]", "{e}");
        assert!(e.reason.ends_with("(line 1)"), "{e}");
        let e = parse_json::<T>("{\"a\": 1, \"c\": 2}", "t.json").unwrap_err();
        assert!(e.reason.contains("unknown field `c`"), "{e}");
        assert!(parse_json::<T>("{\"a\": 1} x", "t.json").is_err());
        let e = parse_toml::<T>("a = [\n", "t.toml").unwrap_err();
        assert!(e.reason.starts_with("invalid TOML"), "{e}");
    }

    #[test]
    fn field_lines_point_at_the_key_or_its_table() {
        let text = "name = \"x\"\n\n[a]\nk = 1\n[a.b]\n  k = 2\nother = 3\n";
        assert_eq!(field_line(text, "name"), " (line 1)");
        assert_eq!(field_line(text, "a.k"), " (line 4)");
        assert_eq!(field_line(text, "a.b.k"), " (line 6)");
        assert_eq!(field_line(text, "a.b.missing"), " (line 5)");
        assert_eq!(field_line(text, "c.k"), "");
    }

    #[test]
    fn reads_bounded_files() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("x.toml");
        std::fs::write(&p, "a = 1.0").unwrap();
        assert_eq!(read_text(&p, "x.toml").unwrap(), "a = 1.0");
        let e = read_text(dir.path(), "dir").unwrap_err();
        assert!(e.reason.starts_with("cannot read"), "{e}");
        #[cfg(unix)]
        {
            let e = read_text(Path::new("/dev/zero"), "/dev/zero").unwrap_err();
            assert!(e.reason.contains("a device"), "{e}");
            let fifo = dir.path().join("fifo");
            let made = std::process::Command::new("mkfifo").arg(&fifo).status();
            if made.is_ok_and(|s| s.success()) {
                let e = read_text(&fifo, "fifo").unwrap_err();
                assert!(e.reason.contains("FIFO"), "{e}");
            }
        }
    }
}
