//! Reports: what the commands print, as text and as JSON.
//!
//! | file | what |
//! |---|---|
//! | [`ccd_queries`] | CCD kernels against query files with exact answers: misses, false positives, time (`cornertree ccd-queries`) |
//! | [`ccd_bench`] | `bench --ccd`'s table: continuous beside discrete per method, and discrete at `k` sub-steps |
//! | [`continuous`] | `run --ccd`'s JSON: per step the pairs with times of impact, the earliest, discrete's misses, the sub-stepped reference's score; totals |
//! | [`animate`] | clip playback: refit containment, tightness, per-frame costs |
//! | [`bench`](mod@bench) | `bench`'s table and the scaling studies' markdown tables |
//! | [`kernels`] | operations charged and paid per kernel, time per test (`cornertree kernels`) |
//! | [`kernel_inputs`] | the seeded mixed inputs of `cornertree kernels` |
//! | [`inspect`] | static mesh summary: counts, de-duplication, tree shape and bytes |
//! | [`paper`] | the paper's published figures, printed beside ours and labelled |
//! | [`run`] | per-frame counters per method and the Tables 2–3 style summary |
//! | [`study`] | the plane-sphere experiment's table per scenario, the paper's column beside it |
//! | [`tables`] | Table 1 and the environment hierarchies per method |

pub mod animate;
pub mod bench;
pub mod ccd_bench;
pub mod ccd_queries;
pub mod continuous;
pub mod inspect;
pub mod kernel_inputs;
pub mod kernels;
pub mod paper;
pub mod rays;
pub mod run;
pub mod study;
pub mod tables;
