//! The layouts recordings open on.

use rerun::blueprint::components::{PanelState, PlayState};
use rerun::blueprint::{
    Blueprint, BlueprintPanel, ContainerLike, Horizontal, SelectionPanel, Spatial3DView, Tabs,
    TextDocumentView, TextLogView, TimePanel, TimeSeriesView, Vertical,
};

use super::layout;

/// A run. Left: the contacts close up (character mesh and skeleton, colliding
/// triangles, environment spheres and sub-triangles reached), the character's
/// spheres of level `sphere_level` (any other level can be switched on in
/// the blueprint panel), and the whole scene. Right: the counters as time
/// series (colliding pairs beside precision and recall); this frame's
/// report, the event log and the scenario.
pub fn run_blueprint(sphere_level: usize) -> Blueprint {
    let contacts = Spatial3DView::new("contacts")
        .with_origin("/")
        .with_contents([
            "/world/avatar/mesh",
            "/world/avatar/skeleton",
            "/world/environment/spheres/**",
            "/world/environment/subdivision",
            "/cd/**",
        ]);
    let level = layout::level_path(layout::AVATAR_SPHERES, sphere_level);
    let spheres = Spatial3DView::new(format!("character spheres, level {sphere_level}"))
        .with_origin("/")
        .with_contents([format!("/{level}"), "/cd/**".to_string()]);
    let scene = Spatial3DView::new("scene").with_origin("/").with_contents([
        "/world/**",
        "/cd/**",
        "- /world/environment/spheres/**",
        "- /world/avatar/spheres/**",
    ]);
    let tests = TimeSeriesView::new("tests and refits per frame").with_contents([
        "/stats/tests/**",
        "/stats/refits",
        "/stats/skinned_vertices",
    ]);
    let ops = TimeSeriesView::new("operations (paper's model)").with_origin("/stats/operations");
    let pairs = TimeSeriesView::new("colliding pairs (reported, exact)")
        .with_contents(["/stats/pairs", "/stats/reference_pairs"]);
    let accuracy = TimeSeriesView::new("precision and recall").with_origin("/stats/accuracy");
    let time = TimeSeriesView::new("time per stage (ms)").with_origin("/stats/time_ms");
    let report =
        TextDocumentView::new("this frame").with_origin(format!("/{}", layout::FRAME_REPORT));
    let info = TextDocumentView::new("scenario").with_origin(format!("/{}", layout::INFO));
    let events = TextLogView::new("events").with_origin(format!("/{}", layout::EVENTS));
    let views: Vec<ContainerLike> = vec![
        Vertical::new([
            Horizontal::new([contacts.into(), spheres.into()]).into(),
            scene.into(),
        ])
        .with_row_shares([3.0, 2.0])
        .into(),
        Vertical::new([
            tests.into(),
            ops.into(),
            Tabs::new([pairs.into(), accuracy.into()]).into(),
            time.into(),
            Tabs::new([report.into(), events.into(), info.into()]).into(),
        ])
        .into(),
    ];
    Blueprint::new(Horizontal::new(views).with_column_shares([3.0, 2.0]))
        .with_auto_views(false)
        .with_blueprint_panel(BlueprintPanel::new().with_state(PanelState::Collapsed))
        .with_selection_panel(SelectionPanel::new().with_state(PanelState::Collapsed))
        .with_time_panel(
            TimePanel::new()
                .with_state(PanelState::Collapsed)
                .with_timeline(layout::FRAME)
                .with_play_state(PlayState::Paused),
        )
}

/// A figure: one 3D view of everything and its caption; the time panel only
/// when the figure has a `timeline` to step through.
pub fn figure_blueprint(title: &str, timeline: Option<&str>) -> Blueprint {
    let view = Spatial3DView::new(title).with_origin("/");
    let caption = TextDocumentView::new("caption").with_origin(format!("/{}", layout::INFO));
    Blueprint::new(Horizontal::new([view.into(), caption.into()]).with_column_shares([4.0, 1.0]))
        .with_auto_views(false)
        .with_blueprint_panel(BlueprintPanel::new().with_state(PanelState::Collapsed))
        .with_selection_panel(SelectionPanel::new().with_state(PanelState::Collapsed))
        .with_time_panel(match timeline {
            Some(t) => TimePanel::new()
                .with_state(PanelState::Collapsed)
                .with_timeline(t),
            None => TimePanel::new().with_state(PanelState::Hidden),
        })
}
