//! The serde derives of a definition (`#[derive(Serialize, Deserialize)]`
//! on the struct in `mechanism!`), applied to the types generated for it.

/// Applies the serde derives of a mechanism's definition to one of its
/// generated types (the coordinates, the motion, the modes): with the
/// `serde` feature, as `#[derive(…)]`; without it, a compile error saying
/// to enable it (the generated types hold this crate's types, whose serde
/// implementations come with the feature).
#[cfg(feature = "serde")]
#[doc(hidden)]
#[macro_export]
macro_rules! __with_serde {
    ([$($path:path),+] $item:item) => {
        #[derive($($path),+)]
        $item
    };
}

/// See the `serde` version.
#[cfg(not(feature = "serde"))]
#[doc(hidden)]
#[macro_export]
macro_rules! __with_serde {
    ([$($path:path),+] $item:item) => {
        ::core::compile_error!(
            "deriving Serialize or Deserialize on a mechanism needs the `serde` feature of \
             kinematics-core: `kinematics-core = { version = \"0.1\", features = [\"serde\"] }`"
        );
        $item
    };
}

/// Nothing: a definition's `#[cfg_attr(…, derive(Serialize, …))]` is
/// served by the `serde` feature (see the other version).
#[cfg(feature = "serde")]
#[doc(hidden)]
#[macro_export]
macro_rules! __serde_required {
    () => {};
}

/// Where a definition derives serde's traits under a `cfg_attr` predicate
/// that holds, the error that says which feature to turn on.
#[cfg(not(feature = "serde"))]
#[doc(hidden)]
#[macro_export]
macro_rules! __serde_required {
    () => {
        ::core::compile_error!(
            "deriving Serialize or Deserialize on a mechanism needs the `serde` feature of \
             kinematics-core: `kinematics-core = { version = \"0.1\", features = [\"serde\"] }`"
        );
    };
}
