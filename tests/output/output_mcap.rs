//! The MCAP a run writes, read back with the `mcap` crate and decoded with Foxglove's types:
//! channels and schemas, one message per frame and per contact, monotonic log times, the same
//! positions and events as the CSV files, and the scene file embedded as metadata.

use crate::common;

use common::fixture::BeadOnFloor;
use foxglove::Decode;
use foxglove::messages::log::Level;
use foxglove::messages::{Log, PointCloud, SceneUpdate};
use std::collections::BTreeMap;
use std::path::Path;
use std::process::Command;

/// Runs `wetbounce run SCENE --formats mcap,csv` into `dir`; returns the MCAP's bytes.
fn run_with_mcap_and_csv(scene: &Path, dir: &Path, extra: &[&str]) -> Vec<u8> {
    let out = Command::new(env!("CARGO_BIN_EXE_wetbounce"))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .arg("run")
        .arg(scene)
        .args(["--formats", "mcap,csv", "--quiet", "--out"])
        .arg(dir)
        .args(extra)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let stem = scene.file_stem().unwrap().to_string_lossy();
    std::fs::read(dir.join(format!("{stem}.mcap"))).unwrap()
}

struct Decoded {
    /// Per topic: (log time, payload).
    messages: BTreeMap<String, Vec<(u64, Vec<u8>)>>,
    /// Per topic: (schema name, schema encoding, message encoding).
    channels: BTreeMap<String, (String, String, String)>,
    metadata: BTreeMap<String, BTreeMap<String, String>>,
}

fn decode(bytes: &[u8]) -> Decoded {
    let summary = mcap::Summary::read(bytes).unwrap().expect("a finished MCAP has a summary");
    let mut channels = BTreeMap::new();
    for c in summary.channels.values() {
        let s = c.schema.as_ref().expect("every channel has a schema");
        channels.insert(c.topic.clone(), (s.name.clone(), s.encoding.clone(), c.message_encoding.clone()));
    }
    let mut metadata = BTreeMap::new();
    for index in &summary.metadata_indexes {
        let m = mcap::read::metadata(bytes, index).unwrap();
        metadata.insert(m.name, m.metadata);
    }
    let mut messages: BTreeMap<String, Vec<(u64, Vec<u8>)>> = BTreeMap::new();
    for m in mcap::MessageStream::new(bytes).unwrap() {
        let m = m.unwrap();
        messages.entry(m.channel.topic.clone()).or_default().push((m.log_time, m.data.into_owned()));
    }
    // The statistics record agrees with what was read.
    let stats = summary.stats.expect("statistics record");
    assert_eq!(stats.message_count as usize, messages.values().map(Vec::len).sum::<usize>());
    assert!(summary.chunk_indexes.iter().all(|c| c.compression == "zstd"));
    Decoded { messages, channels, metadata }
}

fn f64_at(data: &[u8], at: usize) -> f64 {
    f64::from_le_bytes(data[at..at + 8].try_into().unwrap())
}

fn field_offsets(cloud: &PointCloud) -> BTreeMap<String, (u32, i32)> {
    cloud.fields.iter().map(|f| (f.name.clone(), (f.offset, f.r#type))).collect()
}

#[test]
fn mcap_has_foxglove_channels_one_cloud_per_frame_and_the_csv_positions() {
    let dir = tempfile::tempdir().unwrap();
    let scene = Path::new("scenes/toluene_drop.toml");
    let bytes = run_with_mcap_and_csv(scene, dir.path(), &[]);
    let d = decode(&bytes);

    let ch =
        |t: &str, s: &str, e: &str, m: &str| (t.to_string(), (s.to_string(), e.to_string(), m.to_string()));
    assert_eq!(
        d.channels,
        BTreeMap::from([
            ch("/event_log", "foxglove.Log", "protobuf", "protobuf"),
            ch("/events", "wetbounce.ContactEvent", "jsonschema", "json"),
            ch("/particles", "foxglove.PointCloud", "protobuf", "protobuf"),
            ch("/scene", "foxglove.SceneUpdate", "protobuf", "protobuf"),
            ch("/walls", "foxglove.SceneUpdate", "protobuf", "protobuf"),
        ])
    );

    for (topic, msgs) in &d.messages {
        assert!(msgs.windows(2).all(|w| w[0].0 <= w[1].0), "{topic}: log times go back");
    }

    // One cloud per CSV frame, same time, same positions bit for bit.
    let csv = std::fs::read_to_string(dir.path().join("trajectories.csv")).unwrap();
    let rows: Vec<Vec<&str>> = csv.lines().skip(1).map(|l| l.split(',').collect()).collect();
    let clouds = &d.messages["/particles"];
    assert_eq!(clouds.len(), 1001, "1 s at a 1 ms output interval, one particle");
    assert_eq!(clouds.len(), rows.len());
    for ((log_time, data), row) in clouds.iter().zip(&rows) {
        let cloud = PointCloud::decode(&data[..]).unwrap();
        let t: f64 = row[0].parse().unwrap();
        assert_eq!(*log_time, (t * 1e9).round() as u64);
        let ts = cloud.timestamp.unwrap();
        assert_eq!(ts.sec() as u64 * 1_000_000_000 + ts.nsec() as u64, *log_time);
        let fields = field_offsets(&cloud);
        for name in ["x", "y", "z", "id", "diameter", "speed", "state", "kind"] {
            assert!(fields.contains_key(name), "field {name} missing");
        }
        assert_eq!(cloud.data.len(), cloud.point_stride as usize);
        for (k, axis) in ["x", "y", "z"].iter().enumerate() {
            let v = f64_at(&cloud.data, fields[*axis].0 as usize);
            assert_eq!(v, row[2 + k].parse::<f64>().unwrap(), "{axis} at t = {t}");
        }
        let state = cloud.data[fields["state"].0 as usize];
        let name = ["free", "held", "resting"][state as usize];
        assert_eq!(name, row[8], "state at t = {t}");
        assert_eq!(f64_at(&cloud.data, fields["diameter"].0 as usize), 2.75e-3);
    }

    // Walls once on their own topic, the spheres every frame.
    let scene_msgs = &d.messages["/scene"];
    assert_eq!(scene_msgs.len(), clouds.len());
    assert_eq!(d.messages["/walls"].len(), 1);
    let walls = SceneUpdate::decode(&d.messages["/walls"][0].1[..]).unwrap();
    assert_eq!(walls.entities[0].id, "walls");
    assert_eq!(walls.entities[0].cubes.len(), 1, "the plane is drawn as a thin slab");
    let last = SceneUpdate::decode(&scene_msgs.last().unwrap().1[..]).unwrap();
    let sphere = &last.entities[0].spheres[0];
    assert_eq!(sphere.size.as_ref().unwrap().x, 2.75e-3, "spheres at true diameter");

    // One /events message per events.csv row, with the same values.
    let events_csv = std::fs::read_to_string(dir.path().join("events.csv")).unwrap();
    let header: Vec<&str> = events_csv.lines().next().unwrap().split(',').collect();
    let event_rows: Vec<Vec<&str>> = events_csv.lines().skip(1).map(|l| l.split(',').collect()).collect();
    let events = &d.messages["/events"];
    assert_eq!(events.len(), event_rows.len());
    assert_eq!(events.len(), 3);
    for ((log_time, data), row) in events.iter().zip(&event_rows) {
        let json: serde_json::Value = serde_json::from_slice(data).unwrap();
        let keys: Vec<&str> = json.as_object().unwrap().keys().map(String::as_str).collect();
        let mut sorted_header = header.clone();
        sorted_header.sort();
        let mut sorted_keys = keys.clone();
        sorted_keys.sort();
        assert_eq!(sorted_keys, sorted_header, "the fields of events.csv");
        for (k, name) in header.iter().enumerate() {
            let v = &json[*name];
            match v {
                // Both files write the shortest decimal that reads back to the same f64: compare
                // the text, since serde_json's default parser is not exact to the last bit.
                serde_json::Value::Number(_) => {
                    let text = std::str::from_utf8(data).unwrap();
                    assert!(
                        text.contains(&format!("\"{name}\":{},", row[k]))
                            || text.contains(&format!("\"{name}\":{}}}", row[k])),
                        "{name} = {} in {text}",
                        row[k]
                    );
                }
                serde_json::Value::String(s) => assert_eq!(s, row[k]),
                other => panic!("{name}: {other}"),
            }
        }
        assert_eq!(*log_time, (row[0].parse::<f64>().unwrap() * 1e9).round() as u64);
    }

    // The same contacts as lines of Foxglove's Log panel, at the same times, the outcome and
    // the numbers in words; a deposition is a warning.
    let lines = &d.messages["/event_log"];
    assert_eq!(lines.len(), event_rows.len());
    for ((log_time, data), row) in lines.iter().zip(&event_rows) {
        let log = Log::decode(&data[..]).unwrap();
        assert_eq!(*log_time, (row[0].parse::<f64>().unwrap() * 1e9).round() as u64);
        let ts = log.timestamp.unwrap();
        assert_eq!(ts.sec() as u64 * 1_000_000_000 + ts.nsec() as u64, *log_time);
        let outcome = row[header.iter().position(|h| *h == "outcome").unwrap()];
        let wall = row[header.iter().position(|h| *h == "other").unwrap()];
        assert!(
            log.message.starts_with(&format!("particle 0 {outcome} on wall {wall}: V∞ = ")),
            "{}",
            log.message
        );
        let level = if outcome == "deposited" { Level::Warning } else { Level::Info };
        assert_eq!(log.level, level as i32, "{}", log.message);
        assert_eq!(log.name, "wetbounce");
    }

    // Every result carries its inputs.
    let source = std::fs::read_to_string(scene).unwrap();
    assert_eq!(d.metadata["scene"]["source"], source);
    assert_eq!(d.metadata["scene"]["path"], "scenes/toluene_drop.toml");
    assert_eq!(d.metadata["wetbounce"]["version"], env!("CARGO_PKG_VERSION"));
}

#[test]
fn output_interval_flag_sets_the_frame_times_whatever_the_step() {
    let dir = tempfile::tempdir().unwrap();
    let bytes = run_with_mcap_and_csv(
        Path::new("scenes/toluene_drop.toml"),
        dir.path(),
        &["--output-interval", "0.03"],
    );
    let d = decode(&bytes);
    let times: Vec<u64> = d.messages["/particles"].iter().map(|m| m.0).collect();
    // 0, 0.03, …, 0.99 and the end at 1 s: exact multiples, though 0.03 s is 300 steps.
    let mut expected: Vec<u64> = (0..=33).map(|k| k * 30_000_000).collect();
    expected.push(1_000_000_000);
    assert_eq!(times, expected);
}

#[test]
fn walls_of_every_shape_are_drawn_and_spheres_stop_past_the_limit() {
    let dir = tempfile::tempdir().unwrap();
    let meshes = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/meshes/plate.obj");
    let scene = dir.path().join("shapes.toml");
    // A cylinder, a box and a mesh, each of glass.
    let walls = format!(
        r#"
[[walls]]
name = "column"
type = "cylinder"
base = [0.0, 0.0, -0.05]
radius = 0.03
length = 0.2
material = {{ youngs_modulus = 6.0e10, poisson_ratio = 0.23 }}
[[walls]]
name = "floor"
type = "box"
min = [-0.04, -0.04, -0.06]
max = [0.04, 0.04, -0.05]
inside = false
material = {{ youngs_modulus = 6.0e10, poisson_ratio = 0.23 }}
[[walls]]
name = "plate"
type = "mesh"
file = "{}"
material = {{ youngs_modulus = 6.0e10, poisson_ratio = 0.23 }}
"#,
        meshes.display()
    );
    let text = BeadOnFloor::new()
        .dt(1e-4)
        .duration(0.01)
        .output_interval(0.005)
        .integrator("rk2")
        .fluid(1000.0, 1e-3)
        .gravity([0.0, 0.0, -9.81])
        .effects("gravity = {}")
        .restitution_max(0.97)
        .walls(&walls)
        .at([0.0, 0.0, 0.02])
        .at([0.01, 0.0, 0.02])
        .toml();
    std::fs::write(&scene, text).unwrap();
    let bytes = run_with_mcap_and_csv(&scene, dir.path(), &["--max-spheres", "1"]);
    let d = decode(&bytes);
    let walls = SceneUpdate::decode(&d.messages["/walls"][0].1[..]).unwrap();
    let e = &walls.entities[0];
    assert_eq!((e.cylinders.len(), e.cubes.len(), e.triangles.len()), (1, 1, 1));
    let cyl = &e.cylinders[0];
    let size = cyl.size.as_ref().unwrap();
    assert_eq!((size.x, size.y, size.z), (0.06, 0.06, 0.2), "diameter, diameter, length along +Z");
    let centre = cyl.pose.as_ref().unwrap().position.as_ref().unwrap();
    assert!((centre.z - 0.05).abs() < 1e-12, "centre halfway along the axis: {}", centre.z);
    // The plate: 12 triangles.
    assert_eq!(e.triangles[0].indices.len(), 36);
    // Two particles, a limit of one sphere: no spheres entity at all.
    assert!(!d.messages.contains_key("/scene"));
    assert_eq!(d.messages["/particles"].len(), 3);
}

#[test]
fn spheres_at_true_size_at_any_particle_count_unless_limited() {
    // A lattice of more than the 1000 beads that once ended the spheres: every one is a sphere of its
    // own diameter at its own position, in every frame, by default.
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("lattice.toml");
    let text = BeadOnFloor::new()
        .dt(1e-4)
        .duration(2e-4)
        .output_interval(1e-4)
        .fluid(1000.0, 1e-3)
        .gravity([0.0, 0.0, -9.81])
        .effects("gravity = {}")
        .extra(
            "[[lattice]]\nkind = \"glass\"\ndiameter = 1e-3\nmin = [0.0, 0.0, 0.01]\n\
             max = [0.022, 0.022, 0.032]\nspacing = 2e-3",
        )
        .toml();
    std::fs::write(&scene, text).unwrap();
    let d = decode(&run_with_mcap_and_csv(&scene, dir.path(), &[]));
    let frames = &d.messages["/scene"];
    assert_eq!(frames.len(), 3);
    for ((_, spheres), (_, points)) in frames.iter().zip(&d.messages["/particles"]) {
        let cloud = PointCloud::decode(&points[..]).unwrap();
        let n = cloud.data.len() / cloud.point_stride as usize;
        assert!(n > 1000, "{n} beads");
        let update = SceneUpdate::decode(&spheres[..]).unwrap();
        let spheres = &update.entities[0].spheres;
        assert_eq!(spheres.len(), n);
        let fields = field_offsets(&cloud);
        for (i, s) in spheres.iter().enumerate() {
            let at = i * cloud.point_stride as usize;
            let p = s.pose.as_ref().unwrap().position.as_ref().unwrap();
            let xyz = ["x", "y", "z"].map(|a| f64_at(&cloud.data, at + fields[a].0 as usize));
            assert_eq!([p.x, p.y, p.z], xyz, "sphere {i} where its point is");
            let d = f64_at(&cloud.data, at + fields["diameter"].0 as usize);
            assert_eq!(s.size.as_ref().unwrap().x, d, "sphere {i} at its diameter");
        }
    }
    // `--max-spheres` still leaves them out for a smaller file.
    let limited = tempfile::tempdir().unwrap();
    let d = decode(&run_with_mcap_and_csv(&scene, limited.path(), &["--max-spheres", "1000"]));
    assert!(!d.messages.contains_key("/scene"));
}

/// The latest message of `topic` logged at or before `t_ns`, as a viewer that seeks shows it.
fn latest_at<'a>(d: &'a Decoded, topic: &str, t_ns: u64) -> Option<&'a [u8]> {
    d.messages.get(topic)?.iter().rev().find(|(t, _)| *t <= t_ns).map(|(_, data)| &data[..])
}

#[test]
fn a_viewer_seeking_to_any_time_still_has_the_walls_and_the_spheres() {
    let dir = tempfile::tempdir().unwrap();
    let bytes = run_with_mcap_and_csv(Path::new("scenes/toluene_drop.toml"), dir.path(), &[]);
    let d = decode(&bytes);
    // Foxglove keeps, per topic, the latest message before the seek time: at every frame time
    // and between frames, both the walls and the particle's sphere must be there.
    let times: Vec<u64> = d.messages["/particles"].iter().map(|m| m.0).collect();
    let seeks = times.iter().step_by(37).flat_map(|&t| [t, t + 1]);
    for t in seeks {
        let walls = SceneUpdate::decode(latest_at(&d, "/walls", t).expect("walls at every time")).unwrap();
        let wall = walls.entities.iter().find(|e| e.id == "walls").expect("the walls entity");
        assert_eq!(wall.cubes.len(), 1, "the plane's slab at t = {t} ns");
        let scene = SceneUpdate::decode(latest_at(&d, "/scene", t).expect("spheres at every time")).unwrap();
        assert_eq!(scene.entities[0].spheres.len(), 1, "the drop's sphere at t = {t} ns");
    }
}
