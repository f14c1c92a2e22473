//! Options the library names with a word ([`Method`](crate::pipeline::Method),
//! [`SkinningModel`](crate::character::SkinningModel),
//! [`RefitRule`](crate::sphere_tree::refit::RefitRule)): each lists its
//! values, names them, says in one line what each does, and parses its names
//! back (`str::parse`), so that a command line, a settings file or an engine's
//! console can offer them without a copy of the list.

use std::fmt;

/// A closed set of named values.
pub trait Choice: Copy + Sized + 'static {
    /// What a value of the set is called ("method", "skinning model").
    const WHAT: &'static str;
    /// Every value, in the order the library lists them.
    const ALL: &'static [Self];
    /// The value's name (kebab-case, as files and command lines spell it).
    fn name(self) -> &'static str;
    /// One line on what the value does.
    fn summary(self) -> &'static str;
}

/// A name that is none of a [`Choice`]'s.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown {what} {name:?}; one of: {}", known.join(", "))]
pub struct UnknownName {
    /// What was asked for ("method").
    pub what: &'static str,
    /// The name given.
    pub name: String,
    /// The names there are.
    pub known: Vec<&'static str>,
}

/// The value of `T` named `name`.
///
/// ```
/// use cornertree::choice::parse_choice;
/// use cornertree::pipeline::Method;
///
/// assert_eq!(parse_choice::<Method>("pruned-tri-tri"), Ok(Method::PrunedTriTri));
/// let err = parse_choice::<Method>("fastest").unwrap_err();
/// assert!(err.to_string().contains("original"));
/// ```
pub fn parse_choice<T: Choice>(name: &str) -> Result<T, UnknownName> {
    T::ALL
        .iter()
        .copied()
        .find(|v| v.name() == name)
        .ok_or_else(|| UnknownName {
            what: T::WHAT,
            name: name.to_string(),
            known: T::ALL.iter().map(|v| v.name()).collect(),
        })
}

/// `Display` through [`Choice::name`].
pub(crate) fn show<T: Choice>(v: T, f: &mut fmt::Formatter<'_>) -> fmt::Result {
    f.write_str(v.name())
}
