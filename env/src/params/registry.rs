//! Tables of named components (planners, trackers, rigs): a name, a one-line summary and a
//! constructor with the defaults, looked up by name with one error for an unknown name.
//!
//! A [`Table`] is a value: it starts with whatever its owner puts in it (the built-ins) and
//! takes more entries at run time ([`Table::add`]), refusing a duplicate or malformed name.

use std::fmt;
use std::sync::Arc;

use crate::InputError;

/// A constructor of a component of type `T` with its defaults, shareable between threads.
pub type Make<T> = Arc<dyn Fn() -> Box<T> + Send + Sync>;

/// One entry of a table of components of type `T` (`dyn Planner`, `dyn Tracker`).
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

/// Why a table refused an entry.
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

/// A table of components of type `T`, in the order they were added.
pub struct Table<T: ?Sized> {
    what: &'static str,
    entries: Vec<Entry<T>>,
}

impl<T: ?Sized> Clone for Table<T> {
    fn clone(&self) -> Self {
        Table {
            what: self.what,
            entries: self.entries.clone(),
        }
    }
}

impl<T: ?Sized> fmt::Debug for Table<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Table")
            .field("what", &self.what)
            .field("names", &self.names())
            .finish()
    }
}

impl<T: ?Sized> Table<T> {
    /// An empty table of `what`s (`planner`, `tracker`, `rig`: the word its errors use).
    pub fn new(what: &'static str) -> Self {
        Table {
            what,
            entries: Vec::new(),
        }
    }

    /// Adds `entry`; refuses a name already taken or one experiment files cannot name.
    pub fn add(&mut self, entry: Entry<T>) -> Result<(), RegistryError> {
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
        Ok(())
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
