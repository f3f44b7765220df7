//! The recording's default layout (a Rerun blueprint), sent inside the `.rrd` so the viewer opens it
//! with no clicks.
//!
//! Why not `rerun::blueprint::{Tabs, TimeSeriesView, …}`: in the Rust SDK 0.36.3 those builders have
//! no way to set a view's properties (the Python SDK's `time_ranges`, `plot_legend`), and the MSE
//! plots need both (step 0's transient would squash the rest; the legend would cover the curves).
//! So this module logs the same blueprint archetypes the SDK's builders log (`ContainerBlueprint`,
//! `ViewBlueprint`, `ViewContents`, `ViewportBlueprint`, `TimePanelBlueprint`) plus the view
//! properties, into a blueprint store that is sent with [`rerun::RecordingStream::send_blueprint`].
//! Ids are a counter rather than random, so the same experiment always writes the same layout.

use rerun::external::re_log_types::BlueprintActivationCommand;
use rerun::external::re_sdk_types::blueprint::{archetypes as bp, components as bpc};
use rerun::external::re_sdk_types::datatypes;

type BpResult<T> = std::result::Result<T, Box<dyn std::error::Error + Send + Sync>>;

/// A view or container already logged, known by its blueprint entity path.
#[derive(Clone, Debug)]
pub(crate) struct Node {
    path: String,
    id: [u8; 16],
}

/// What a view plots.
pub(crate) enum ViewKind {
    /// Scalars against the `step` timeline; `from_step` hides earlier steps (a visible range);
    /// the x axis opens on `from_step` (or 0) to `last_step`; the legend in the `legend` corner.
    TimeSeries {
        from_step: Option<i64>,
        last_step: i64,
        legend: bpc::Corner2D,
    },
    BarChart,
    TextDocument,
    Spatial2D,
}

/// A blueprint being written: every view and container is logged as soon as it is made.
pub(crate) struct Layout {
    rec: rerun::RecordingStream,
    storage: rerun::sink::MemorySinkStorage,
    next: u64,
}

impl Layout {
    pub fn new(application_id: &'static str) -> BpResult<Self> {
        // A blueprint store is a recording of kind Blueprint on the `blueprint` timeline; the
        // builder's `blueprint()` is what the SDK's own `Blueprint::send` uses.
        let (rec, storage) = rerun::RecordingStreamBuilder::new(application_id).blueprint().memory()?;
        rec.set_time_sequence("blueprint", 0);
        Ok(Layout { rec, storage, next: 0 })
    }

    /// A fresh id: a version-4-shaped UUID whose bits are a counter, not randomness.
    fn id(&mut self) -> [u8; 16] {
        self.next += 1;
        let mut b = [0u8; 16];
        b[..8].copy_from_slice(&0xf17e_4b00_0000_0000u64.to_be_bytes());
        b[8..].copy_from_slice(&self.next.to_be_bytes());
        b[6] = (b[6] & 0x0f) | 0x40;
        b[8] = (b[8] & 0x3f) | 0x80;
        b
    }

    fn uuid_string(b: &[u8; 16]) -> String {
        let h = crate::numerics::linalg::hex(b);
        format!("{}-{}-{}-{}-{}", &h[0..8], &h[8..12], &h[12..16], &h[16..20], &h[20..32])
    }

    /// A view named `name` showing the entities that `contents` (entity path filter lines such as
    /// `+ /mse/white/**`) selects.
    pub fn view(&mut self, kind: ViewKind, name: &str, contents: &[String]) -> BpResult<Node> {
        let id = self.id();
        let path = format!("view/{}", Self::uuid_string(&id));
        let class = match kind {
            ViewKind::TimeSeries { .. } => "TimeSeries",
            ViewKind::BarChart => "BarChart",
            ViewKind::TextDocument => "TextDocument",
            ViewKind::Spatial2D => "2D",
        };
        self.rec.log(
            format!("{path}/ViewContents"),
            &bp::ViewContents::new(contents.iter().map(|q| bpc::QueryExpression(q.as_str().into()))),
        )?;
        self.rec.log(
            path.as_str(),
            &bp::ViewBlueprint::new(bpc::ViewClass(class.into())).with_display_name(name).with_space_origin("/"),
        )?;
        if let ViewKind::BarChart = kind {
            // Its legend would name each bar by its whole entity path, over the bars; the bars
            // follow the table beside them and have the filters' colours.
            self.rec.log(format!("{path}/PlotLegend"), &bp::PlotLegend::new().with_visible(false))?;
        }
        if let ViewKind::TimeSeries { from_step, last_step, legend } = kind {
            self.rec
                .log(format!("{path}/PlotLegend"), &bp::PlotLegend::new().with_corner(legend).with_visible(true))?;
            // Without it the viewer (0.36.3) opens every plot on a window of about two thousand
            // steps around the cursor: a decimated horizon of 10⁵ or 10⁶ steps would show its
            // first few buckets, and the envelope that keeps a late spike visible would be off
            // screen.
            let whole = datatypes::TimeRange {
                start: datatypes::TimeRangeBoundary::Absolute(from_step.unwrap_or(0).into()),
                end: datatypes::TimeRangeBoundary::Absolute(last_step.into()),
            };
            self.rec.log(format!("{path}/TimeAxis"), &bp::TimeAxis::new().with_view_range(bpc::TimeRange(whole)))?;
            if let Some(start) = from_step {
                let range = datatypes::VisibleTimeRange {
                    timeline: "step".into(),
                    range: datatypes::TimeRange {
                        start: datatypes::TimeRangeBoundary::Absolute(start.into()),
                        end: datatypes::TimeRangeBoundary::Infinite,
                    },
                };
                self.rec.log(format!("{path}/VisibleTimeRanges"), &bp::VisibleTimeRanges::new([range]))?;
            }
        }
        Ok(Node { path, id })
    }

    /// A container of `children`, shown as tabs, side by side, stacked or in a grid.
    pub(crate) fn container(&mut self, kind: bpc::ContainerKind, name: &str, children: &[Node]) -> BpResult<Node> {
        self.container_with_shares(kind, name, children, &[])
    }

    /// A container whose children get the given shares of its width (horizontal) or height
    /// (vertical); equal shares when `shares` is empty.
    pub(crate) fn container_with_shares(
        &mut self,
        kind: bpc::ContainerKind,
        name: &str,
        children: &[Node],
        shares: &[f32],
    ) -> BpResult<Node> {
        let id = self.id();
        let path = format!("container/{}", Self::uuid_string(&id));
        let mut arch = bp::ContainerBlueprint::new(kind)
            .with_display_name(name)
            .with_contents(children.iter().map(|c| bpc::IncludedContent::from(c.path.as_str())));
        if !shares.is_empty() {
            let s = shares.iter().map(|x| bpc::ColumnShare((*x).into()));
            arch = match kind {
                bpc::ContainerKind::Vertical => arch.with_row_shares(shares.iter().map(|x| bpc::RowShare((*x).into()))),
                _ => arch.with_col_shares(s),
            };
        }
        if kind == bpc::ContainerKind::Tabs {
            if let Some(first) = children.first() {
                arch = arch.with_active_tab(first.path.as_str());
            }
        }
        self.rec.log(path.as_str(), &arch)?;
        Ok(Node { path, id })
    }

    /// Makes `root` the whole viewport, with the time panel on the `step` timeline (playing in a
    /// loop when `animate`, e.g. a string that moves; else paused), and sends the blueprint into
    /// `target` as its active and default layout.
    pub(crate) fn send(self, root: &Node, animate: bool, target: &rerun::RecordingStream) -> BpResult<()> {
        self.rec.log(
            "viewport",
            &bp::ViewportBlueprint::new()
                .with_root_container(bpc::RootContainer(datatypes::Uuid::from(root.id)))
                .with_auto_layout(false)
                .with_auto_views(false),
        )?;
        // The views need the room more than the selection panel; the time panel keeps only its
        // playback bar (the `step` cursor moves the string of seed 004).
        self.rec.log("selection_panel", &bp::PanelBlueprint::new().with_state(bpc::PanelState::Collapsed))?;
        self.rec.log(
            "time_panel",
            &bp::TimePanelBlueprint::new()
                .with_timeline("step")
                .with_state(bpc::PanelState::Collapsed)
                .with_play_state(if animate { bpc::PlayState::Playing } else { bpc::PlayState::Paused })
                .with_loop_mode(if animate { bpc::LoopMode::All } else { bpc::LoopMode::Off }),
        )?;
        let msgs = self.storage.take();
        let Some(blueprint_id) = msgs.first().map(|m| m.store_id().clone()) else {
            return Err("the blueprint store wrote no message".into());
        };
        target.send_blueprint(msgs, BlueprintActivationCommand { blueprint_id, make_active: true, make_default: true });
        Ok(())
    }
}
