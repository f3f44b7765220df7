//! The recording of every shipped experiment (small trial counts), read back with rerun's own
//! decoder: no chunk without rows (the viewer's time panel panics on one), a default blueprint
//! that is activated, and one colour per filter in every view, different filters different.

use std::collections::{BTreeMap, BTreeSet};
use std::io::BufReader;

use filterbench::config;
use filterbench::report::recording::{self, style};
use rerun::external::re_log_encoding::DecoderApp;
use rerun::external::re_sdk_types::blueprint::archetypes as bp;
use rerun::external::re_sdk_types::blueprint::components::{self as bpc, QueryExpression};
use rerun::external::re_sdk_types::datatypes::TimeRangeBoundary;
use rerun::log::{Chunk, LogMsg};
use rerun::{ComponentIdentifier, StoreKind};

const KINDS: [&str; 9] =
    ["mse", "promise", "trajectories", "compare", "tables", "summary", "design", "galerkin", "string"];

/// Who an entity's colours belong to, from the documented path layout.
enum Owner {
    /// One filter, named by the path.
    Filter(String),
    /// One series per filter, in the file's order.
    EveryFilter,
    Other,
}

fn owner(parts: &[&str]) -> Owner {
    match parts {
        ["mse" | "promise", _, f, _] | ["compare", _, f] | ["design", f, _] => Owner::Filter(f.to_string()),
        ["galerkin", _, "string", l] if *l != "truth" => Owner::Filter(l.to_string()),
        ["trajectories", _, _, _, "estimates" | "errors"] => Owner::EveryFilter,
        _ => Owner::Other,
    }
}

struct Read {
    data_entities: usize,
    blueprint_chunks: usize,
    viewport: bool,
    activated: bool,
    colours: BTreeMap<String, BTreeSet<[u8; 3]>>,
    truth: BTreeSet<[u8; 3]>,
    /// `design/<filter>/line_search_<s>` entities (seed 000 Fig. 1), without the variant.
    line_searches: BTreeSet<String>,
    /// `trajectories/…/z<j>/noise_free` entities (seed 003 Figs. 3–4), with the variant, and their colours.
    noise_free: BTreeSet<String>,
    noise_free_colours: BTreeSet<[u8; 3]>,
    /// The blueprint's view contents that name a noise-free entity.
    noise_free_shown: usize,
    /// Time-series views, and the x-axis view ranges (first and last step) the blueprint sets.
    time_series_views: usize,
    time_axes: Vec<(i64, i64)>,
}

fn colour_components() -> Vec<ComponentIdentifier> {
    vec![
        rerun::SeriesLines::descriptor_colors().component,
        rerun::SeriesPoints::descriptor_colors().component,
        rerun::BarChart::descriptor_color().component,
        rerun::LineStrips2D::descriptor_colors().component,
    ]
}

fn read(path: &std::path::Path, variants: &[String], filters: &[String]) -> Read {
    let file = BufReader::new(std::fs::File::open(path).unwrap());
    let mut r = Read {
        data_entities: 0,
        blueprint_chunks: 0,
        viewport: false,
        activated: false,
        colours: BTreeMap::new(),
        truth: BTreeSet::new(),
        line_searches: BTreeSet::new(),
        noise_free: BTreeSet::new(),
        noise_free_colours: BTreeSet::new(),
        noise_free_shown: 0,
        time_series_views: 0,
        time_axes: Vec::new(),
    };
    let mut entities = BTreeSet::new();
    for msg in DecoderApp::decode_lazy(file) {
        match msg.expect("the recording decodes") {
            LogMsg::SetStoreInfo(_) => {}
            LogMsg::BlueprintActivationCommand(c) => r.activated |= c.make_active && c.make_default,
            LogMsg::ArrowMsg(store, m) => {
                let chunk = Chunk::from_arrow_msg(&m).expect("a chunk");
                let entity = chunk.entity_path().to_string();
                assert!(chunk.num_rows() > 0, "{}: chunk with zero rows at {entity}", path.display());
                if store.kind() == StoreKind::Blueprint {
                    r.blueprint_chunks += 1;
                    r.viewport |= entity == "/viewport";
                    let id = rerun::external::re_sdk_types::blueprint::archetypes::ViewContents::descriptor_query()
                        .component;
                    for row in chunk.iter_component::<QueryExpression>(id) {
                        r.noise_free_shown += row.iter().filter(|q| q.0.as_str().ends_with("/noise_free")).count();
                    }
                    let class = bp::ViewBlueprint::descriptor_class_identifier().component;
                    for row in chunk.iter_component::<bpc::ViewClass>(class) {
                        r.time_series_views += row.iter().filter(|c| c.0.as_str() == "TimeSeries").count();
                    }
                    for row in chunk.iter_component::<bpc::TimeRange>(bp::TimeAxis::descriptor_view_range().component) {
                        for t in row.iter() {
                            let at = |b: &TimeRangeBoundary| match b {
                                TimeRangeBoundary::Absolute(t) => t.0,
                                other => panic!("{}: an x axis bound {other:?}, not a step", path.display()),
                            };
                            r.time_axes.push((at(&t.0.start), at(&t.0.end)));
                        }
                    }
                    continue;
                }
                entities.insert(entity);
                let parts: Vec<String> = chunk.entity_path().iter().map(|p| p.unescaped_str().to_string()).collect();
                let mut parts: Vec<&str> = parts.iter().map(String::as_str).collect();
                if parts.first().is_some_and(|p| variants.iter().any(|v| v == p) && !KINDS.contains(p)) {
                    parts.remove(0);
                }
                if parts.first() == Some(&"trajectories") && parts.last() == Some(&"noise_free") {
                    r.noise_free.insert(chunk.entity_path().to_string());
                }
                if let ["design", f, leaf] = parts.as_slice()
                    && leaf.starts_with("line_search_")
                {
                    r.line_searches.insert(format!("{f}/{leaf}"));
                }
                for id in colour_components() {
                    for row in chunk.iter_component::<rerun::components::Color>(id) {
                        for (i, c) in row.iter().enumerate() {
                            let [red, g, b, _] = c.to_array();
                            let who = match owner(&parts) {
                                Owner::Filter(f) => f,
                                Owner::EveryFilter => filters[i].clone(),
                                Owner::Other => {
                                    if parts.last() == Some(&"truth") {
                                        r.truth.insert([red, g, b]);
                                    }
                                    if parts.last() == Some(&"noise_free") {
                                        r.noise_free_colours.insert([red, g, b]);
                                    }
                                    continue;
                                }
                            };
                            r.colours.entry(who).or_default().insert([red, g, b]);
                        }
                    }
                }
            }
        }
    }
    r.data_entities = entities.len();
    r
}

#[test]
fn every_shipped_recording_has_no_empty_chunk_a_blueprint_and_one_colour_per_filter() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments");
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok()?.path().file_stem()?.to_str().map(str::to_string))
        .collect();
    names.sort();
    assert!(names.len() >= 11, "the shipped experiments: {names:?}");
    let tmp = crate::common::TempDir::new();
    for name in &names {
        let mut exps = config::load_variants(&dir.join(format!("{name}.toml")), &Default::default()).expect("parses");
        for e in &mut exps {
            e.trials = 40;
            e.sample_trajectories = e.sample_trajectories.min(2);
        }
        let outs: Vec<_> = exps.iter().map(|e| filterbench::pipeline::run(e, false).expect("runs")).collect();
        let runs: Vec<_> = exps.iter().zip(&outs).collect();
        let path = tmp.path().join(format!("{name}.rrd"));
        recording::write(&runs, &path).expect("writes");
        let variants: Vec<String> = exps.iter().filter_map(|e| e.variant.clone()).collect();
        let names_in_order: Vec<String> = exps[0].filters.iter().map(|f| f.name.clone()).collect();
        let r = read(&path, &variants, &names_in_order);
        assert!(r.data_entities > 0, "{name}: data");
        assert!(r.viewport && r.activated && r.blueprint_chunks > 3, "{name}: a default blueprint, activated");
        // Every plot opens on its whole horizon (the viewer's default is a window of about two
        // thousand steps around the cursor, a few buckets of a decimated long horizon).
        assert!(r.time_series_views > 0, "{name}: plots");
        assert_eq!(r.time_axes.len(), r.time_series_views, "{name}: every plot sets its x range");
        let horizons: BTreeSet<i64> = exps.iter().map(|e| e.plant.horizon as i64).collect();
        for (first, last) in &r.time_axes {
            assert!(*first <= 1 && horizons.contains(last), "{name}: x axis {first}..{last}, horizons {horizons:?}");
        }
        let filters: BTreeSet<&str> = exps[0].filters.iter().map(|f| f.name.as_str()).collect();
        let mut seen: BTreeMap<[u8; 3], String> = BTreeMap::new();
        for (f, cs) in &r.colours {
            assert!(filters.contains(f.as_str()), "{name}: {f} is a filter");
            assert_eq!(cs.len(), 1, "{name}: filter {f} has one colour in every view, not {cs:?}");
            let c = *cs.iter().next().unwrap();
            if let Some(other) = seen.insert(c, f.clone()) {
                panic!("{name}: filters {other} and {f} share the colour {c:?}");
            }
            let [red, g, b, _] = style::DROPOUT;
            assert_ne!(c, [red, g, b], "{name}: {f} has the dropout markers' colour");
            assert!(!r.truth.contains(&c), "{name}: {f} has the truth's colour");
            assert!(!r.noise_free_colours.contains(&c), "{name}: {f} has the noise-free z's colour");
        }
        // The noise-free z (seed 003 Figs. 3–4): one entity per sample trial and component where the
        // plant has a known input, in every scenario's sample-trial view; none where it has none.
        let sampled: usize = exps
            .iter()
            .zip(&outs)
            .map(|(e, o)| o.scenarios.iter().map(|s| s.trajectories.len()).sum::<usize>() * e.plant.nz())
            .sum();
        if exps[0].plant.known_input.is_empty() {
            assert!(r.noise_free.is_empty(), "{name}: no known input, no noise-free z: {:?}", r.noise_free);
            assert_eq!(r.noise_free_shown, 0, "{name}: no view shows a noise-free z");
        } else {
            assert_eq!(r.noise_free.len(), sampled, "{name}: a noise-free z per sample trial and component");
            assert_eq!(r.noise_free_colours.len(), 1, "{name}: one colour for the noise-free z");
            let shown: usize = exps
                .iter()
                .zip(&outs)
                .map(|(e, o)| o.scenarios.iter().filter(|s| !s.trajectories.is_empty()).count() * e.plant.nz().min(2))
                .sum();
            assert_eq!(r.noise_free_shown, shown, "{name}: each sample-trial view of z shows it");
        }
        match name.as_str() {
            "aniso_dropout" => assert!(!r.noise_free.is_empty(), "aniso_dropout draws the noise-free z"),
            "aniso_multiplicative" => assert!(r.noise_free.is_empty(), "aniso_multiplicative has no known input"),
            _ => {}
        }
        assert_eq!(r.colours.len(), filters.len(), "{name}: every filter is drawn");
        // Every kept line search of Algorithm 1 is drawn (seed 000 Fig. 1), and nothing else.
        let expected: BTreeSet<String> = exps
            .iter()
            .zip(&outs)
            .flat_map(|(e, o)| e.filters.iter().zip(&o.filters))
            .flat_map(|(f, d)| {
                d.design.line_searches.iter().map(move |l| format!("{}/line_search_{}", f.name, l.iteration))
            })
            .collect();
        assert_eq!(r.line_searches, expected, "{name}: the line searches drawn");
        if name == "minimax_example3" {
            assert!(expected.contains("minimax/line_search_1"), "Example 3 draws Fig. 1");
        }
    }
}

#[test]
fn names_that_differ_stay_different_entities() {
    let a = recording::path(&["mse", "k.1"]);
    let b = recording::path(&["mse", "k_1"]);
    let c = recording::path(&["mse", "k/1"]);
    assert_ne!(a, b);
    assert_ne!(b, c);
    assert_eq!(
        rerun::EntityPath::parse_strict(&c).expect("a valid path").len(),
        2,
        "a '/' in a name stays inside one part: {c}"
    );
}
