//! Tables chosen by `kind` (`shape = { kind = "student_t", nu = 6 }`), read strictly: every key the
//! kind does not take is an error that names the key and lists the valid ones, also for kinds
//! without parameters (serde ignores extra keys there even with `deny_unknown_fields`), and a kind
//! without parameters may be written as its bare name (`shape = "laplace"`).

use serde::Deserialize;
use serde::de::{DeserializeOwned, Deserializer, Error as _};

/// An enum read from a `kind` table: what the table is called in messages, and each kind's keys
/// besides `kind` (the list must match the enum's variants; tests/it/strict_files.rs checks it).
pub trait Kinds: DeserializeOwned {
    const WHAT: &'static str;
    const KINDS: &'static [(&'static str, &'static [&'static str])];
}

/// Accepts a bare kind name or a table and checks its keys against `kinds`; returns the table with
/// `kind` in it. `open` kinds take any further key (a `given` covariance names its blocks).
pub(crate) fn check_table(
    what: &str,
    kinds: &[(&str, &[&str])],
    open: &[&str],
    value: toml::Value,
) -> Result<toml::Table, String> {
    let known = || kinds.iter().map(|(k, _)| format!("\"{k}\"")).collect::<Vec<_>>().join(", ");
    let table = match value {
        toml::Value::String(s) => {
            let mut t = toml::Table::new();
            t.insert("kind".into(), toml::Value::String(s));
            t
        }
        toml::Value::Table(t) => t,
        other => {
            return Err(format!(
                "invalid type: {}, expected a {what} as a kind name or a table {{ kind = … }} (kinds: {})",
                other.type_str(),
                known()
            ));
        }
    };
    let kind = match table.get("kind") {
        Some(toml::Value::String(k)) => k.clone(),
        Some(other) => return Err(format!("`kind` must be a string, found {}", other.type_str())),
        None => return Err(format!("missing field `kind` (kinds: {})", known())),
    };
    let Some((_, keys)) = kinds.iter().find(|(k, _)| *k == kind) else {
        return Err(format!("unknown {what} kind `{}` (kinds: {})", kind.escape_debug(), known()));
    };
    if !open.contains(&kind.as_str()) {
        if let Some(bad) = table.keys().find(|k| *k != "kind" && !keys.contains(&k.as_str())) {
            let valid: Vec<String> =
                std::iter::once("kind").chain(keys.iter().copied()).map(|k| format!("`{k}`")).collect();
            return Err(format!(
                "unknown field `{}` for {what} kind `{kind}` (valid keys: {})",
                bad.escape_debug(),
                valid.join(", ")
            ));
        }
    }
    Ok(table)
}

/// Reads a [`Kinds`] enum strictly (see the module doc); errors inside the table name their key.
pub(crate) fn strict<'de, D: Deserializer<'de>, T: Kinds>(d: D) -> Result<T, D::Error> {
    let table = check_table(T::WHAT, T::KINDS, &[], toml::Value::deserialize(d)?).map_err(D::Error::custom)?;
    serde_path_to_error::deserialize(toml::Value::Table(table)).map_err(|e| {
        let path = e.path().to_string();
        let msg = e.inner().message().trim().to_string();
        D::Error::custom(if path == "." { msg } else { format!("`{path}`: {msg}") })
    })
}

/// A field holding a [`Kinds`] enum read with [`strict`] (for places a `deserialize_with` cannot
/// reach, such as the values of a map).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Strict<T>(pub T);

impl<'de, T: Kinds> Deserialize<'de> for Strict<T> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        strict(d).map(Strict)
    }
}

impl<T: Default> Default for Strict<T> {
    fn default() -> Self {
        Strict(T::default())
    }
}
