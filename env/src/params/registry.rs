//! Tables of named components (the planners, the trackers): a name, a one-line summary and a
//! constructor with the defaults, looked up by name with one error for an unknown name.

use crate::InputError;

/// One entry of a table of components of type `T` (`dyn Planner`, `dyn Tracker`).
pub struct Entry<T: ?Sized> {
    /// The registry name.
    pub name: &'static str,
    /// One line on what it is.
    pub summary: &'static str,
    make: fn() -> Box<T>,
}

impl<T: ?Sized> Entry<T> {
    /// The entry `name`, made with its defaults by `make`.
    pub const fn new(name: &'static str, summary: &'static str, make: fn() -> Box<T>) -> Self {
        Entry {
            name,
            summary,
            make,
        }
    }

    /// A new one, with its defaults.
    pub fn make(&self) -> Box<T> {
        (self.make)()
    }
}

/// The names in `table`.
pub fn names<T: ?Sized>(table: &[Entry<T>]) -> Vec<&'static str> {
    table.iter().map(|e| e.name).collect()
}

/// The entry of `table` called `name`; otherwise an error naming `source`, the field `what`
/// (`planner`, `tracker`) and the known names.
pub fn lookup<'a, T: ?Sized>(
    table: &'a [Entry<T>],
    source: &str,
    what: &str,
    name: &str,
) -> Result<&'a Entry<T>, InputError> {
    table.iter().find(|e| e.name == name).ok_or_else(|| {
        InputError::new(
            source,
            what,
            format!(
                "unknown {what} {name:?} (known: {})",
                names(table).join(", ")
            ),
        )
    })
}
