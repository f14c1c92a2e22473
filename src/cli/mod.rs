//! The command-line front, one command per file; each parses its arguments,
//! calls into the library and formats through `report`.
//!
//! | file | command |
//! |---|---|
//! | [`args`] | arguments `run`, `compare`, `bench` and `scaling` share |
//! | [`inspect`] | `inspect`: a mesh's sphere tree; `--animate` checks refit |
//! | [`tables`] | `tables`: Table 1 and each method's hierarchy sizes |
//! | [`run`] | `run`: a scenario through its methods, recorded |
//! | [`compare`] | `compare`: every method against the ground truth |
//! | [`play`] | the frame loop `run` and `compare` share: a session of the scenario's methods, stepped frame by frame |
//! | [`observe`] | what watches that loop: the ground truth, `--ccd`, the report, the recordings, a frame dump, the progress bar |
//! | [`bench`] | `bench`: cost per frame against the parry3d baseline |
//! | [`scaling`] | `scaling`: cost against character, room and crowd size |
//! | [`rays`] | `rays`: ray casts against posed characters, exact reference, parry3d baseline |
//! | [`figures`] | `figures`: recordings of the paper's Figures 1-3 |
//! | [`kernels`] | `kernels`: operations charged and paid per kernel |
//! | [`ccd_queries`] | `ccd-queries`: the continuous kernels on query files with exact answers |
//! | [`study`] | `plane-sphere-study`: one condition changed at a time |

pub mod args;
pub mod bench;
pub mod ccd_queries;
pub mod compare;
pub mod figures;
pub mod inspect;
pub mod kernels;
pub mod observe;
pub mod play;
pub mod rays;
pub mod run;
pub mod scaling;
pub mod study;
pub mod tables;

/// Writes to stdout; a reader that went away (`| head`) ends the program quietly.
pub fn emit(text: &str) -> anyhow::Result<()> {
    use std::io::Write;
    let mut stdout = std::io::stdout().lock();
    match stdout
        .write_all(text.as_bytes())
        .and_then(|()| stdout.flush())
    {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        other => Ok(other?),
    }
}
