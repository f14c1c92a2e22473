//! The layouts recordings open on.

use rerun::blueprint::{
    Blueprint, ContainerLike, Horizontal, Spatial3DView, Tabs, TextDocumentView, TextLogView,
    TimeSeriesView, Vertical,
};

use super::layout;

/// A run: the whole scene and a close-up on the character (its spheres, the
/// environment spheres and sub-triangles it reached, the colliding pairs)
/// above, the counters as time series and this frame's report, the event
/// log and the scenario beside them.
pub fn run_blueprint() -> Blueprint {
    let scene = Spatial3DView::new("scene").with_origin("/").with_contents([
        "/world/**",
        "/cd/**",
        "- /world/environment/spheres/**",
        "- /world/avatar/spheres/**",
    ]);
    let close_up = Spatial3DView::new("close-up: spheres and contacts")
        .with_origin("/")
        .with_contents([
            "/world/avatar/**",
            "/world/environment/spheres/**",
            "/world/environment/subdivision",
            "/cd/**",
        ]);
    let tests = TimeSeriesView::new("tests per frame").with_origin("/stats/tests");
    let ops = TimeSeriesView::new("operations (paper's model)").with_contents([
        "/stats/operations",
        "/stats/pairs",
        "/stats/refits",
    ]);
    let time = TimeSeriesView::new("time per stage (ms)").with_origin("/stats/time_ms");
    let report =
        TextDocumentView::new("this frame").with_origin(format!("/{}", layout::FRAME_REPORT));
    let info = TextDocumentView::new("scenario").with_origin(format!("/{}", layout::INFO));
    let events = TextLogView::new("events").with_origin(format!("/{}", layout::EVENTS));
    let views: Vec<ContainerLike> = vec![
        Vertical::new([close_up.into(), scene.into()])
            .with_row_shares([3.0, 2.0])
            .into(),
        Vertical::new([
            tests.into(),
            ops.into(),
            time.into(),
            Tabs::new([report.into(), events.into(), info.into()]).into(),
        ])
        .into(),
    ];
    Blueprint::new(Horizontal::new(views).with_column_shares([3.0, 2.0])).with_auto_views(false)
}

/// A figure: one 3D view of everything and its caption.
pub fn figure_blueprint(title: &str) -> Blueprint {
    let view = Spatial3DView::new(title).with_origin("/");
    let caption = TextDocumentView::new("caption").with_origin(format!("/{}", layout::INFO));
    Blueprint::new(Horizontal::new([view.into(), caption.into()]).with_column_shares([4.0, 1.0]))
        .with_auto_views(false)
}
