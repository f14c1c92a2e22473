//! A run's recording ends with rerun's footer (what `rerun rrd verify`
//! checks and the viewer seeks by), written when the run finishes; the data
//! read back is the streamed data; a file over the size limit is left as
//! streamed.

use std::path::Path;
use std::process::Command;

use cornertree_workbench::record::footer::{Footer, add_footer, finish_file};

#[path = "common/rrd.rs"]
#[allow(dead_code)]
mod rrd;

/// Whether the file ends with an RRD stream footer (`RRF2` `FOOT` and the
/// count of footers it points to).
fn has_stream_footer(path: &Path) -> bool {
    let bytes = std::fs::read(path).unwrap();
    let tail = &bytes[bytes.len().saturating_sub(16)..];
    tail.windows(8).any(|w| w == b"RRF2FOOT")
}

#[test]
fn a_finished_run_leaves_a_footer_and_the_same_data() {
    let dir = std::env::temp_dir().join(format!("cornertree-footer-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let rec = dir.join("run.rrd");
    let scenario = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/cesium_man.toml");
    let o = Command::new(env!("CARGO_BIN_EXE_cornertree"))
        .args([
            "run",
            scenario.to_str().unwrap(),
            "--frames",
            "3",
            "--method",
            "undivided-pruned-tri-tri",
            "--no-truth",
            "--save",
        ])
        .arg(&rec)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(has_stream_footer(&rec), "the run's recording has no footer");
    assert!(
        !dir.join("run.rrd.with-footer").exists(),
        "no file left beside it"
    );
    let with = rrd::read_rrd(&rec);
    assert!(with.error.is_none(), "{:?}", with.error);
    assert!(with.has_blueprint);
    let frames = with.frames("stats/pairs");
    assert_eq!(frames.len(), 3, "{frames:?}");

    // Written again: the same chunks, still one footer at the end.
    let chunks = with.chunks.len();
    let n = add_footer(&rec).unwrap();
    assert!(n as usize >= chunks);
    let again = rrd::read_rrd(&rec);
    assert!(again.error.is_none());
    assert_eq!(again.chunks.len(), chunks);
    assert_eq!(again.entity_paths(), with.entity_paths());
    assert!(has_stream_footer(&rec));

    // Over the limit: left as it is.
    let before = std::fs::read(&rec).unwrap();
    match finish_file(&rec, 1000).unwrap() {
        Footer::TooLarge(size) => assert_eq!(size as usize, before.len()),
        other => panic!("{other:?}"),
    }
    assert_eq!(std::fs::read(&rec).unwrap(), before);
    // Not a recording: an error, and the file untouched.
    let junk = dir.join("junk.rrd");
    std::fs::write(&junk, b"not a recording at all").unwrap();
    assert!(add_footer(&junk).is_err());
    assert_eq!(std::fs::read(&junk).unwrap(), b"not a recording at all");
    assert!(!dir.join("junk.rrd.with-footer").exists());
}
