//! Registries of named components (planners, trackers, rigs, scenario families): a name, a
//! one-line summary and a constructor with the defaults, looked up by name with one error for an
//! unknown name.
//!
//! A [`Registry`] is a value: it starts with whatever its owner puts in it (the built-ins) and
//! takes more entries at run time ([`Registry::add`]), refusing a duplicate or malformed name.
//! A component made under another name than its own reports the registry name through
//! [`Renamed`].

use std::fmt;
use std::sync::Arc;

use crate::InputError;
use crate::input::Rejection;
use crate::params::{ParamError, ParamInfo, ParamSet};

/// A constructor of a component of type `T` with its defaults, shareable between threads.
pub type Make<T> = Arc<dyn Fn() -> Box<T> + Send + Sync>;

/// One entry of a registry of components of type `T` (`dyn Planner`, `dyn Tracker`).
pub struct Entry<T: ?Sized> {
    name: Arc<str>,
    summary: Arc<str>,
    make: Make<T>,
    serial: bool,
}

impl<T: ?Sized> Clone for Entry<T> {
    fn clone(&self) -> Self {
        Entry {
            name: self.name.clone(),
            summary: self.summary.clone(),
            make: self.make.clone(),
            serial: self.serial,
        }
    }
}

impl<T: ?Sized> fmt::Debug for Entry<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Entry")
            .field("name", &self.name)
            .field("summary", &self.summary)
            .field("serial", &self.serial)
            .finish_non_exhaustive()
    }
}

impl<T: ?Sized> Entry<T> {
    /// The entry `name`, made with its defaults by `make`.
    pub fn new(
        name: &str,
        summary: &str,
        make: impl Fn() -> Box<T> + Send + Sync + 'static,
    ) -> Self {
        Entry {
            name: name.into(),
            summary: summary.into(),
            make: Arc::new(make),
            serial: false,
        }
    }

    /// The same entry, whose runs go one at a time: what it makes holds a lock that one
    /// thread owns at a time (a Python plugin holds the GIL), so a sweep runs no two of its
    /// runs at once, and says so.
    pub fn serial(mut self) -> Self {
        self.serial = true;
        self
    }

    /// Whether its runs go one at a time ([`Entry::serial`]).
    pub fn is_serial(&self) -> bool {
        self.serial
    }

    /// The registry name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// One line on what it is.
    pub fn summary(&self) -> &str {
        &self.summary
    }

    /// A new one, with its defaults.
    pub fn make(&self) -> Box<T> {
        (self.make)()
    }
}

/// Why a registry refused an entry.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum RegistryError {
    /// The name is taken.
    #[error("a {what} called {name:?} is already registered")]
    Duplicate {
        /// `planner`, `tracker` or `rig`.
        what: &'static str,
        /// The name given.
        name: String,
    },
    /// The name cannot be written in an experiment file.
    #[error("{what} name {name:?}: {reason}")]
    BadName {
        /// `planner`, `tracker` or `rig`.
        what: &'static str,
        /// The name given.
        name: String,
        /// What is wrong with it.
        reason: NameError,
    },
}

/// A name that experiment files and the command line cannot write.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error(
    "a name is letters, digits, '_', '-' and '.', with an optional family prefix such as `ompl:`"
)]
pub struct NameError;

/// Checks that `name` can be written where experiment files and the command line name
/// components: letters, digits, `_`, `-` and `.`, with an optional family prefix (`ompl:rrt`).
pub fn check_name(name: &str) -> Result<(), NameError> {
    let word = |s: &str| {
        !s.is_empty()
            && s.chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-' || c == '.')
    };
    let ok = match name.split_once(':') {
        Some((family, rest)) => word(family) && word(rest),
        None => word(name),
    };
    if ok { Ok(()) } else { Err(NameError) }
}

/// A registry of components of type `T`, in the order they were added.
pub struct Registry<T: ?Sized> {
    what: &'static str,
    entries: Vec<Entry<T>>,
}

impl<T: ?Sized> Clone for Registry<T> {
    fn clone(&self) -> Self {
        Registry {
            what: self.what,
            entries: self.entries.clone(),
        }
    }
}

impl<T: ?Sized> fmt::Debug for Registry<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Registry")
            .field("what", &self.what)
            .field("names", &self.names())
            .finish()
    }
}

impl<T: ?Sized> Registry<T> {
    /// An empty registry of `what`s (`planner`, `tracker`, `rig`: the word its errors use).
    pub fn new(what: &'static str) -> Self {
        Registry {
            what,
            entries: Vec::new(),
        }
    }

    /// A registry of `what`s holding `entries`; refuses a name taken twice or a malformed one.
    pub fn of(
        what: &'static str,
        entries: impl IntoIterator<Item = Entry<T>>,
    ) -> Result<Self, RegistryError> {
        let mut r = Registry::new(what);
        for e in entries {
            r.add_entry(e)?;
        }
        Ok(r)
    }

    /// Adds `name` (`summary`: one line on what it is), made with its defaults by `make`;
    /// refuses a name already taken or one experiment files cannot write.
    pub fn add(
        &mut self,
        name: &str,
        summary: &str,
        make: impl Fn() -> Box<T> + Send + Sync + 'static,
    ) -> Result<&mut Self, RegistryError> {
        self.add_entry(Entry::new(name, summary, make))
    }

    /// Adds `entry` (made with [`Entry::new`], perhaps [`Entry::serial`]); refuses a name
    /// already taken or one experiment files cannot write.
    pub fn add_entry(&mut self, entry: Entry<T>) -> Result<&mut Self, RegistryError> {
        check_name(entry.name()).map_err(|reason| RegistryError::BadName {
            what: self.what,
            name: entry.name().to_string(),
            reason,
        })?;
        if self.get(entry.name()).is_some() {
            return Err(RegistryError::Duplicate {
                what: self.what,
                name: entry.name().to_string(),
            });
        }
        self.entries.push(entry);
        Ok(self)
    }

    /// The entry called `name`, if any.
    pub fn get(&self, name: &str) -> Option<&Entry<T>> {
        self.entries.iter().find(|e| e.name() == name)
    }

    /// The entry called `name`; otherwise an error naming `source`, the field (`planner`,
    /// `tracker`) and the known names.
    pub fn lookup(&self, source: &str, name: &str) -> Result<&Entry<T>, InputError> {
        let what = self.what;
        self.get(name).ok_or_else(|| {
            InputError::new(
                source,
                what,
                format!(
                    "unknown {what} {name:?} (known: {})",
                    self.names().join(", ")
                ),
            )
        })
    }

    /// The names, in the order they were added.
    pub fn names(&self) -> Vec<&str> {
        self.entries.iter().map(|e| e.name()).collect()
    }

    /// The entries, in the order they were added.
    pub fn iter(&self) -> impl Iterator<Item = &Entry<T>> {
        self.entries.iter()
    }
}

/// A component under its registry name, when that differs from the name it reports itself:
/// the owner's trait (`Planner`, `Tracker`) is implemented for `Renamed<dyn Trait>` by
/// answering `name` and passing every other call to `inner`.
pub struct Renamed<T: ?Sized> {
    /// The registry name.
    pub name: String,
    /// The component.
    pub inner: Box<T>,
}

impl<T: ParamSet + ?Sized> ParamSet for Renamed<T> {
    fn params(&self) -> Vec<ParamInfo> {
        self.inner.params()
    }
    fn set_param(&mut self, key: &str, value: &str) -> Result<(), ParamError> {
        self.inner.set_param(key, value)
    }
    fn check_params(&self) -> Result<(), Rejection> {
        self.inner.check_params()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    type Maker = dyn Fn() -> u8 + Send + Sync;

    fn entry(name: &str) -> Entry<Maker> {
        Entry::new(name, "a test entry", || Box::new(|| 1u8) as Box<Maker>)
    }

    #[test]
    fn refuses_duplicate_and_malformed_names_and_lists_the_known_ones() {
        let mut r = Registry::of("widget", [entry("a"), entry("lab:b.2")]).unwrap();
        assert_eq!(r.names(), ["a", "lab:b.2"]);
        let e = r.add_entry(entry("a")).err().unwrap();
        assert_eq!(e.to_string(), "a widget called \"a\" is already registered");
        for bad in ["", "a b", "a{b}", "x:", ":x", "a:b:c", "é"] {
            let e = r.add(bad, "", || Box::new(|| 2u8) as Box<Maker>).err();
            assert!(
                matches!(e, Some(RegistryError::BadName { what: "widget", .. })),
                "{bad:?}: {e:?}"
            );
        }
        assert!(Registry::of("widget", [entry("c"), entry("c")]).is_err());
        let e = r.lookup("exp.toml", "z").err().unwrap();
        assert_eq!(
            e.to_string(),
            "exp.toml: widget: unknown widget \"z\" (known: a, lab:b.2)"
        );
        assert_eq!((r.get("a").unwrap().make())(), 1);
    }
}
