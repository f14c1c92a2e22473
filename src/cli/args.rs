//! The arguments `run`, `compare`, `bench` and `scaling` share (scenario,
//! methods, frames, JSON report, edge de-duplication), and small value parsers.

use std::path::PathBuf;

use cornertree::choice::{Choice, parse_choice};
use cornertree::pipeline::Method;
use cornertree_workbench::scenario::Resolved;

/// Which scenario to play, how much of it, and where the JSON report goes.
#[derive(clap::Args, Clone, Debug)]
pub struct ScenarioArgs {
    /// A scenario file (TOML; see docs/scenarios.md and scenarios/). Default:
    /// the paper-scale living room.
    #[arg(default_value = "scenarios/living_room.toml")]
    pub scenario: PathBuf,
    /// Play only this method (repeat for several); default: the scenario's
    /// methods (`bench` and `scaling`: every method).
    #[arg(long = "method", value_parser = choice::<Method>())]
    pub methods: Vec<Method>,
    /// Play this many frames instead of the scenario's (`scaling`: frames per
    /// configuration, default 16).
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..))]
    pub frames: Option<u64>,
    /// Write the report as JSON to this file (fields: docs/scenarios.md for
    /// `run` and `compare`, docs/performance.md for `bench` and `scaling`).
    #[arg(long)]
    pub json: Option<PathBuf>,
    /// Edge de-duplication (paper §4): `on` or `off` whatever the scenario
    /// says (`--dedup` alone: on). Default: as the scenario says for `run`
    /// and `compare`; off for `bench` and `scaling`, so the
    /// triangle-triangle methods find exactly parry's pairs.
    #[arg(long, value_enum, num_args = 0..=1, default_missing_value = "on")]
    pub dedup: Option<Switch>,
    /// Same as `--dedup off`.
    #[arg(long, conflicts_with = "dedup")]
    pub no_dedup: bool,
}

/// On or off.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Switch {
    On,
    Off,
}

impl ScenarioArgs {
    /// De-duplication asked on the command line, if any.
    pub fn dedup_override(&self) -> Option<bool> {
        if self.no_dedup {
            Some(false)
        } else {
            self.dedup.map(|s| s == Switch::On)
        }
    }

    /// Applies methods and de-duplication to a resolved scenario; with no
    /// de-duplication asked, `dedup_default` (`None`: the scenario's).
    pub fn apply(&self, resolved: &mut Resolved, dedup_default: Option<bool>) {
        if !self.methods.is_empty() {
            resolved.methods = self.methods.clone();
        }
        if let Some(d) = self.dedup_override().or(dedup_default) {
            resolved.dedup = d;
        }
    }

    /// The methods asked, or every method.
    pub fn methods_or_all(&self) -> Vec<Method> {
        if self.methods.is_empty() {
            Method::ALL.to_vec()
        } else {
            self.methods.clone()
        }
    }
}

/// A positive finite number.
pub fn parse_positive(s: &str) -> Result<f32, String> {
    let r: f32 = s.parse().map_err(|e| format!("{e}"))?;
    if r.is_finite() && r > 0.0 {
        Ok(r)
    } else {
        Err("must be a positive number".into())
    }
}

/// Three finite numbers separated by commas.
pub fn parse_offset(s: &str) -> Result<[f32; 3], String> {
    let parts: Vec<&str> = s.split(',').collect();
    if parts.len() != 3 {
        return Err(format!(
            "expected three numbers X,Y,Z separated by commas, got {} value(s)",
            parts.len()
        ));
    }
    let mut out = [0.0f32; 3];
    for (o, (p, axis)) in out.iter_mut().zip(parts.iter().zip(["X", "Y", "Z"])) {
        let x: f32 = p
            .trim()
            .parse()
            .map_err(|e| format!("{axis} = {:?}: {e}", p.trim()))?;
        if !x.is_finite() {
            return Err(format!("{axis} = {:?} is not a finite number", p.trim()));
        }
        *o = x;
    }
    Ok(out)
}

/// A parser of one of the library's named options ([`Choice`]: methods,
/// skinning models, refit rules): its names are the possible values, each
/// with its one-line summary in `--help`.
pub fn choice<T: Choice + Send + Sync>() -> impl clap::builder::TypedValueParser<Value = T> {
    use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
    PossibleValuesParser::new(
        T::ALL
            .iter()
            .map(|v| PossibleValue::new(v.name()).help(v.summary())),
    )
    .map(|name| parse_choice::<T>(&name).expect("clap accepts only the possible values"))
}
