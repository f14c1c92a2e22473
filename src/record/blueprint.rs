//! The layouts recordings open on.

use rerun::blueprint::components::{PanelState, PlayState};
use rerun::blueprint::{
    Blueprint, BlueprintPanel, ContainerLike, Horizontal, SelectionPanel, Spatial3DView, Tabs,
    TextDocumentView, TextLogView, TimePanel, TimeSeriesView, Vertical,
};

use super::framing::{Bounds, Eye, FramedBlueprint, view_path};
use super::layout;

/// A run, of one character or a world. Left: the bodies close up (meshes,
/// skeletons, the colliding triangles coloured by pair kind with the room's
/// side as outlines, the room spheres and sub-triangles the traversal
/// reached), each character's refit spheres of level `sphere_level` (the
/// other levels, and the objects' spheres, can be switched on in the
/// blueprint panel), and the whole scene. Right: the tests and refits, the
/// operations and colliding pairs per kind (and the exact pairs), precision
/// and recall per kind and in total, the time per stage; this frame's
/// report, the event log and the scenario. Views list bodies by wildcard,
/// so the layout is the same for one character or a crowd.
///
/// With `first_frame` (the bodies' box at frame 0, `framing::first_frame_bounds`),
/// the contacts and spheres views open looking at it (`framing`): left to
/// themselves they frame what the whole recording holds, which cuts bodies
/// off at frame 0; the scene view frames the room well by itself.
pub fn run_blueprint(
    characters: &[String],
    objects: &[String],
    sphere_level: usize,
    first_frame: Option<Bounds>,
) -> FramedBlueprint {
    // Entity filters take `**` only at the end: each body's spheres are left
    // out by name.
    let no_spheres: Vec<String> = characters
        .iter()
        .chain(objects)
        .map(|b| format!("- /{b}/spheres/**"))
        .collect();
    // The bodies without the room (nor the room's side of the contacts): the
    // view frames the characters, not the walls.
    let contacts: ContainerLike = Spatial3DView::new("contacts")
        .with_origin("/")
        .with_contents(
            [
                // The view coordinates (Y up) are logged on `/world` itself.
                format!("/{}", layout::WORLD),
                format!("/{}/**", layout::WORLD_CHARACTERS),
                format!("/{}/**", layout::WORLD_OBJECTS),
                format!("/{}/**", layout::ENV_SPHERES),
                format!("/{}", layout::ENV_SUBDIVISION),
                "/cd/**".to_string(),
                format!("- /{}/environment/room", layout::COLLIDING),
                format!("- /{}/environment/room", layout::FALSE_POSITIVE),
                format!("- /{}/environment/room", layout::FALSE_NEGATIVE),
            ]
            .into_iter()
            .chain(no_spheres.iter().cloned()),
        )
        .into();
    let scene = Spatial3DView::new("scene").with_origin("/").with_contents(
        [
            "/world/**".to_string(),
            "/cd/**".to_string(),
            format!("- /{}/**", layout::ENV_SPHERES),
        ]
        .into_iter()
        .chain(no_spheres),
    );
    let mut sphere_paths: Vec<String> = std::iter::once(format!("/{}", layout::WORLD))
        .chain(characters.iter().map(|c| {
            format!(
                "/{}",
                layout::level_path(&format!("{c}/spheres"), sphere_level)
            )
        }))
        .collect();
    // The characters' side of the contacts only (a wall's triangles are
    // metres long and would crowd the spheres).
    sphere_paths.extend([
        "/cd/**".to_string(),
        format!("- /{}/environment/room", layout::COLLIDING),
        format!("- /{}/environment/room", layout::FALSE_POSITIVE),
        format!("- /{}/environment/room", layout::FALSE_NEGATIVE),
    ]);
    let spheres: ContainerLike =
        Spatial3DView::new(format!("character spheres, level {sphere_level}"))
            .with_origin("/")
            .with_contents(sphere_paths)
            .into();
    // Both close-up views look at the bodies' first frame.
    let eyes: Vec<Eye> = [&contacts, &spheres]
        .into_iter()
        .filter_map(|view| Some(first_frame?.eye(view_path(view)?)))
        .collect();
    let by_kind = |title: &str, counter: &str| {
        TimeSeriesView::new(title).with_origin(format!("/{}/by_kind/{counter}", layout::STATS))
    };
    let tests = TimeSeriesView::new("tests and refits per frame").with_contents([
        "/stats/tests/**",
        "/stats/refits",
        "/stats/skinned_vertices",
    ]);
    let pairs = TimeSeriesView::new("colliding pairs (reported, exact)")
        .with_contents(["/stats/pairs", "/stats/reference_pairs"]);
    let accuracy = TimeSeriesView::new("precision and recall").with_origin("/stats/accuracy");
    let time = TimeSeriesView::new("time per stage (ms)").with_origin("/stats/time_ms");
    let report =
        TextDocumentView::new("this frame").with_origin(format!("/{}", layout::FRAME_REPORT));
    let info = TextDocumentView::new("scenario").with_origin(format!("/{}", layout::INFO));
    let events = TextLogView::new("events").with_origin(format!("/{}", layout::EVENTS));
    let views: Vec<ContainerLike> = vec![
        Vertical::new([Horizontal::new([contacts, spheres]).into(), scene.into()])
            .with_row_shares([3.0, 2.0])
            .into(),
        Vertical::new([
            Tabs::new([
                tests.into(),
                by_kind("sphere-sphere tests per kind", "sphere_sphere").into(),
                by_kind("triangle-triangle tests per kind", "tri_tri").into(),
                by_kind("plane-sphere tests per kind", "plane_sphere").into(),
                by_kind("sphere-box tests per kind", "sphere_box").into(),
                by_kind("box-box tests per kind", "box_box").into(),
            ])
            .into(),
            Tabs::new([
                TimeSeriesView::new("operations (paper's model)")
                    .with_origin("/stats/operations")
                    .into(),
                by_kind("operations per kind", "operations").into(),
            ])
            .into(),
            Tabs::new([
                pairs.into(),
                by_kind("colliding pairs per kind", "pairs").into(),
                accuracy.into(),
            ])
            .into(),
            time.into(),
            Tabs::new([report.into(), events.into(), info.into()]).into(),
        ])
        .into(),
    ];
    FramedBlueprint {
        blueprint: frames_paused(Blueprint::new(
            Horizontal::new(views).with_column_shares([3.0, 2.0]),
        )),
        eyes,
    }
}

/// Only the views: the blueprint and selection panels collapsed, the time
/// panel collapsed on the frame timeline, paused at the start.
fn frames_paused(b: Blueprint) -> Blueprint {
    b.with_auto_views(false)
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

/// `run --ccd` (one character or a world): on the left the bodies at a
/// step's time of impact with the pairs touching there and the swept
/// spheres of the step's touching leaves (only `cd/ccd`, so the camera frames
/// them), beside them a close-up of the pairs and spheres alone, and the
/// scene at the frame below; on the right continuous
/// detection's counters per step, then the events (each step's pairs and
/// time of impact), this frame's report and the scenario. `bodies` are the
/// entities whose `spheres` subtrees the scene leaves out. It opens on the
/// last frame (a run stopped with `--frames` right after a step of
/// interest shows that step).
pub fn ccd_blueprint(bodies: &[String]) -> Blueprint {
    let toi = Spatial3DView::new("time of impact (continuous detection)")
        .with_origin("/")
        .with_contents([format!("/{}/**", layout::CCD)]);
    let close = Spatial3DView::new("touching pairs and swept spheres")
        .with_origin("/")
        .with_contents([
            format!("/{}", layout::CCD_TOI_PAIRS),
            format!("/{}", layout::CCD_TOI_OTHER),
            format!("/{}", layout::CCD_SWEPT),
        ]);
    let scene = Spatial3DView::new("scene at the frame")
        .with_origin("/")
        .with_contents(
            [
                "/world/**".to_string(),
                "/cd/**".to_string(),
                format!("- /{}/**", layout::CCD),
                format!("- /{}/**", layout::ENV_SPHERES),
            ]
            .into_iter()
            .chain(bodies.iter().map(|b| format!("- /{b}/spheres/**"))),
        );
    let ccd = TimeSeriesView::new("continuous detection per step")
        .with_origin(format!("/{}/ccd", layout::STATS));
    let report =
        TextDocumentView::new("this frame").with_origin(format!("/{}", layout::FRAME_REPORT));
    let info = TextDocumentView::new("scenario").with_origin(format!("/{}", layout::INFO));
    let events = TextLogView::new("events").with_origin(format!("/{}", layout::EVENTS));
    let views: Vec<ContainerLike> = vec![
        Vertical::new([
            Horizontal::new([toi.into(), close.into()]).into(),
            scene.into(),
        ])
        .with_row_shares([3.0, 2.0])
        .into(),
        Vertical::new([
            ccd.into(),
            Tabs::new([events.into(), report.into(), info.into()]).into(),
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
                .with_play_state(PlayState::Following),
        )
}

/// `cornertree rays`: left, the rays (to their first hit, or on), the hit
/// points and the characters' meshes, with the spheres the rays refit from
/// level `from_level` down (the levels above are metres wide and hide the
/// rest); right, the spheres the rays refit this frame below the root (the
/// root holds the whole character), and the hits per frame.
pub fn rays_blueprint(characters: &[String], from_level: usize, levels: usize) -> Blueprint {
    let mut close: Vec<String> = vec![format!("/{}", layout::WORLD), "/world/rays/**".to_string()];
    let mut refit: Vec<String> = vec![
        format!("/{}", layout::WORLD),
        "/world/rays/hit_points".into(),
    ];
    for c in characters {
        close.push(format!("/{c}/mesh"));
        close.extend((from_level..levels).map(|l| format!("/{c}/refit_by_rays/level_{l}")));
        refit.extend((1..levels).map(|l| format!("/{c}/refit_by_rays/level_{l}")));
    }
    let rays = Spatial3DView::new("rays, hits and the spheres they refit")
        .with_origin("/")
        .with_contents(close);
    let spheres = Spatial3DView::new("spheres refit by the rays, below the root")
        .with_origin("/")
        .with_contents(refit);
    let stats = TimeSeriesView::new("rays that hit a character").with_origin("/stats");
    frames_paused(Blueprint::new(
        Horizontal::new([
            rays.into(),
            Vertical::new([spheres.into(), stats.into()])
                .with_row_shares([3.0, 1.0])
                .into(),
        ])
        .with_column_shares([3.0, 2.0]),
    ))
}
