//! Names from a mechanism's definition, as the error and sweep types hold
//! them: `&'static str`. With the `serde` feature, a deserialized name is
//! interned: each distinct name is allocated once for the life of the
//! program (the set of names is that of the mechanisms' definitions), so
//! that deserializing needs no input that lives for `'static`.

/// A name from a mechanism's definition (a coordinate, a point, an
/// equation, an option).
pub type Name = &'static str;

/// Coordinates by name, with their values.
pub type Configuration = alloc::vec::Vec<(Name, f64)>;

/// `s` as a `&'static str`, allocated once per distinct name: the names of
/// deserialized errors and of models defined at run time.
#[cfg(any(feature = "serde", feature = "runtime"))]
pub(crate) fn intern(s: &str) -> Name {
    use std::collections::BTreeSet;
    use std::string::String;
    use std::sync::Mutex;

    static TABLE: Mutex<BTreeSet<Name>> = Mutex::new(BTreeSet::new());
    let mut table = match TABLE.lock() {
        Ok(t) => t,
        // A panic elsewhere while holding the lock leaves the set
        // intact: it only ever grows.
        Err(poisoned) => poisoned.into_inner(),
    };
    if let Some(&known) = table.get(s) {
        return known;
    }
    let leaked: Name = std::boxed::Box::leak(String::from(s).into_boxed_str());
    table.insert(leaked);
    leaked
}

/// `names` as a `&'static [Name]`, allocated once per distinct list: the
/// unknowns of the blocks of models defined at run time.
#[cfg(feature = "runtime")]
pub(crate) fn intern_list(names: &[Name]) -> &'static [Name] {
    use std::collections::BTreeSet;
    use std::sync::Mutex;

    static TABLE: Mutex<BTreeSet<&'static [Name]>> = Mutex::new(BTreeSet::new());
    let mut table = match TABLE.lock() {
        Ok(t) => t,
        // As for `intern`: the set only ever grows.
        Err(poisoned) => poisoned.into_inner(),
    };
    if let Some(&known) = table.get(names) {
        return known;
    }
    let leaked: &'static [Name] = std::boxed::Box::leak(names.to_vec().into_boxed_slice());
    table.insert(leaked);
    leaked
}

#[cfg(feature = "serde")]
mod de {
    use std::string::String;
    use std::vec::Vec;

    use serde::{Deserialize, Deserializer};

    use super::{Configuration, Name, intern};

    /// Deserializes a [`Name`].
    pub(crate) fn name<'de, D: Deserializer<'de>>(d: D) -> Result<Name, D::Error> {
        let s = String::deserialize(d)?;
        Ok(intern(&s))
    }

    /// Deserializes a [`Configuration`].
    pub(crate) fn configuration<'de, D: Deserializer<'de>>(
        d: D,
    ) -> Result<Configuration, D::Error> {
        let v: Vec<(String, f64)> = Vec::deserialize(d)?;
        Ok(v.into_iter().map(|(n, x)| (intern(&n), x)).collect())
    }
}

#[cfg(feature = "serde")]
pub(crate) use de::{configuration, name};
