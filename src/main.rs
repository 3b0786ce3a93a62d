//! The `wetbounce` command line: `run` a scene, `check` it, or `recover` a cut MCAP.

use clap::{Parser, Subcommand};
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use wetbounce::fluid::field::OutsideField;
use wetbounce::output::{Folder, Format, OutputError, Progress};
use wetbounce::ranks::comm::Comm;
use wetbounce::ranks::{Split, SplitReport};
use wetbounce::run::checkpoint::SavedScene;
use wetbounce::run::{CheckpointPolicy, Checkpoints, Driver, Ended, RunReport, StopSignals};
use wetbounce::scene::{LoadOptions, Scene, field_report, kind_reports};

/// Particles and drops bouncing on walls in a viscous fluid (Legendre et al. 2006).
#[derive(Parser)]
#[command(version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

/// The options of `run`.
#[derive(clap::Args)]
struct RunArgs {
    /// The scene file (TOML).
    scene: PathBuf,
    /// Output folder [default: out/<scene file stem>/].
    #[arg(long)]
    out: Option<PathBuf>,
    /// Worker threads [default: all cores]. Results do not depend on it.
    #[arg(long, value_parser = clap::value_parser!(u16).range(1..))]
    threads: Option<u16>,
    /// Files to write, comma-separated: mcap, csv, rrd, vtk [default: mcap, and rrd in a build with
    /// the `rerun` feature].
    #[arg(long, value_delimiter = ',', num_args = 1..)]
    formats: Option<Vec<Format>>,
    /// Simulated time between output frames (s) [default: the scene's
    /// simulation.output_interval]. Independent of the time step.
    #[arg(long, value_name = "SECONDS")]
    output_interval: Option<f64>,
    /// In the MCAP, draw particles as spheres on /scene only up to this many particles [default:
    /// every count]; beyond N only the point cloud on /particles has them (drawn in pixels, not
    /// at their size), and the file is 1.2 to 1.4 times smaller.
    #[arg(long, value_name = "N")]
    max_spheres: Option<usize>,
    /// No progress bar (it is also hidden when standard error is not a terminal).
    #[arg(long, short)]
    quiet: bool,
    /// Accept a run of more than 10⁷ output frames or 10¹⁰ time steps (refused otherwise).
    #[arg(long)]
    allow_long_run: bool,
    /// Accept a run whose estimated memory is more than this machine has available (refused
    /// otherwise).
    #[arg(long)]
    allow_large_memory: bool,
    /// Accept a run whose estimated output is more than the output folder's free disk space
    /// (refused otherwise).
    #[arg(long)]
    allow_large_output: bool,
    #[command(flatten)]
    checkpoints: CheckpointArgs,
}

/// When a run checkpoints (docs/output.md, "Checkpoints"); each overrides the scene's
/// `[checkpoint]` key. A run stopped by SIGINT, SIGTERM or SIGHUP always takes one.
#[derive(clap::Args, Clone, Copy)]
struct CheckpointArgs {
    /// Take a checkpoint every S seconds of simulated time, into DIR/checkpoints/.
    #[arg(long, value_name = "S")]
    checkpoint_every: Option<f64>,
    /// Take a checkpoint every MIN minutes of wall-clock time (what a batch queue's limit needs).
    #[arg(long, value_name = "MIN")]
    checkpoint_wall: Option<f64>,
    /// Keep the newest K checkpoints [default: 2].
    #[arg(long, value_name = "K", value_parser = clap::value_parser!(u32).range(1..))]
    checkpoint_keep: Option<u32>,
}

impl CheckpointArgs {
    /// The policy: these options over the scene's keys.
    fn policy(&self, scene: &wetbounce::scene::CheckpointKeys) -> Result<CheckpointPolicy, String> {
        let given = (
            self.checkpoint_every.or(scene.every),
            self.checkpoint_wall.or(scene.wall_minutes),
            self.checkpoint_keep.map(|k| k as usize).or(scene.keep),
        );
        CheckpointPolicy::checked(given, ["--checkpoint-every", "--checkpoint-wall", "--checkpoint-keep"])
    }
}

#[derive(Subcommand)]
enum Command {
    /// Run a scene; writes DIR/<scene>.mcap (and, on request, CSV files and a rerun recording).
    Run(RunArgs),
    /// Validate a scene and print each particle kind's time scales and bounce regime.
    Check {
        /// The scene file (TOML).
        scene: PathBuf,
        /// Accept a run of more than 10⁷ output frames or 10¹⁰ time steps (refused otherwise).
        #[arg(long)]
        allow_long_run: bool,
        /// Accept a run whose estimated memory is more than this machine has available
        /// (refused otherwise).
        #[arg(long)]
        allow_large_memory: bool,
        /// Also say how a run on K ranks (`mpirun -np K`) would split the scene's particles at
        /// its start: particles per rank, clusters, balance (docs/distributed.md).
        #[arg(long, value_name = "K", value_parser = clap::value_parser!(u16).range(1..))]
        ranks: Option<u16>,
    },
    /// Go on with a run from one of its checkpoints (DIR/checkpoints/checkpoint-*.wbck): the CSV
    /// files and the ParaView collection continue where the checkpoint left them, an MCAP
    /// continues as DIR/<scene>.part<N>.mcap, summary.json covers the whole run.
    Resume {
        /// The checkpoint file.
        checkpoint: PathBuf,
        /// Output folder [default: the checkpointed run's]. The files of the run so far are
        /// copied there first.
        #[arg(long)]
        out: Option<PathBuf>,
        /// A scene that changes only simulation.duration (longer), simulation.output_interval
        /// or [checkpoint] [default: the checkpoint's own copy of the scene].
        #[arg(long)]
        scene: Option<PathBuf>,
        /// Files to write [default: the checkpointed run's].
        #[arg(long, value_delimiter = ',', num_args = 1..)]
        formats: Option<Vec<Format>>,
        /// Worker threads [default: all cores]. Results do not depend on it.
        #[arg(long, value_parser = clap::value_parser!(u16).range(1..))]
        threads: Option<u16>,
        /// No progress bar.
        #[arg(long, short)]
        quiet: bool,
        #[command(flatten)]
        checkpoints: CheckpointArgs,
    },
    /// Rewrite the readable part of an MCAP cut short (a killed run, a full disk) as a valid
    /// file: every message up to the last whole frame.
    Recover {
        /// The cut MCAP file.
        input: PathBuf,
        /// The file to write [default: INPUT with `.recovered.mcap` for `.mcap`].
        output: Option<PathBuf>,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Run(args) => on_ranks(|comm| run_scene(&args, comm)),
        Command::Check { scene, allow_long_run, allow_large_memory, ranks } => {
            check_scene(&scene, LoadOptions { allow_long_run, allow_large_memory }, ranks.map(usize::from))
                .map(|text| (text, ExitCode::SUCCESS))
        }
        Command::Resume { checkpoint, out, scene, formats, threads, quiet, checkpoints } => {
            let args = ResumeArgs { checkpoint, out, scene, formats, threads, quiet, checkpoints };
            on_ranks(|comm| resume_run(&args, comm))
        }
        Command::Recover { input, output } => {
            recover_mcap(&input, output.as_deref()).map(|text| (text, ExitCode::SUCCESS))
        }
    };
    match result {
        Ok((text, code)) => {
            // Reading only the head of the output (`| head`) closes the pipe: not an error.
            let mut stdout = std::io::stdout().lock();
            match stdout.write_all(text.as_bytes()).and_then(|()| stdout.flush()) {
                Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
                    eprintln!("error: cannot write to standard output: {e}");
                    ExitCode::FAILURE
                }
                _ => code,
            }
        }
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
    }
}

/// Runs `go` with the ranks of the run: under `mpirun -np K` (K > 1) the run is split over them
/// (docs/distributed.md); started alone, an MPI build is one process like any other (`None`).
fn on_ranks(
    go: impl FnOnce(Option<&dyn Comm>) -> Result<(String, ExitCode), String>,
) -> Result<(String, ExitCode), String> {
    if let Some(code) = launched_without_mpi() {
        return Ok((String::new(), code));
    }
    #[cfg(feature = "mpi")]
    let mpi = wetbounce::ranks::mpi::Mpi::init();
    #[cfg(feature = "mpi")]
    let comm = mpi.as_ref().map(|m| m as &dyn Comm).filter(|c| c.size() > 1);
    #[cfg(not(feature = "mpi"))]
    let comm: Option<&dyn Comm> = None;
    go(comm)
}

/// A build without the `mpi` feature started by `mpirun -np K` (K > 1) would run K copies of the
/// same run writing the same files: refused, by rank 0 (Open MPI's and MPICH's variables tell);
/// the other copies stop quietly.
fn launched_without_mpi() -> Option<ExitCode> {
    if cfg!(feature = "mpi") {
        return None;
    }
    let var = |names: &[&str]| names.iter().find_map(|n| std::env::var(n).ok()?.parse::<u64>().ok());
    let size = var(&["OMPI_COMM_WORLD_SIZE", "PMI_SIZE"])?;
    if size < 2 {
        return None;
    }
    if var(&["OMPI_COMM_WORLD_RANK", "PMI_RANK"]).unwrap_or(0) == 0 {
        eprintln!(
            "error: started on {size} MPI ranks, but this wetbounce was built without MPI: the {size} \
             copies would each run the whole scene and write the same files. Build it with \
             `cargo build --release --features mpi` (docs/distributed.md), or run it alone"
        );
    }
    Some(ExitCode::FAILURE)
}

fn run_scene(args: &RunArgs, comm: Option<&dyn Comm>) -> Result<(String, ExitCode), String> {
    // First of all, so that a signal that comes while the scene loads also stops the run
    // cleanly (after its first frame) rather than killing it.
    let signals = StopSignals::install().map_err(|e| format!("cannot install the signal handlers: {e}"))?;
    let root = comm.is_none_or(|c| c.rank() == 0);
    drive(comm, prepare_run(args, (root, comm.is_some())), &signals)
}

/// Steps a prepared run (a fresh or a resumed one) to its end: in this process, or split over
/// the ranks of `comm` (docs/distributed.md). Returns the end-of-run report, empty on ranks
/// other than 0, and the exit status.
fn drive(
    comm: Option<&dyn Comm>,
    prepared: Result<Prepared, String>,
    signals: &StopSignals,
) -> Result<(String, ExitCode), String> {
    let root = comm.is_none_or(|c| c.rank() == 0);
    // On ranks, every rank goes on or none does: one that stopped alone would leave the others
    // waiting for it. Rank 0 names the error; the others stop quietly.
    if let Some(c) = comm
        && c.any(prepared.is_err())
    {
        return match prepared {
            Err(e) if root => Err(e),
            _ => Ok((String::new(), ExitCode::FAILURE)),
        };
    }
    let Prepared { scene, mut driver, mut progress, mut sim, output_interval, path } = prepared?;
    let Some(comm) = comm else {
        let result = driver.run(&mut sim, vec![&mut progress], signals.flag());
        return Ok(finish_run(driver, &sim, result, (&scene, &path, output_interval), signals));
    };
    let mut split = Split::new(comm, &sim)
        .map_err(|e| format!("{}: cannot hold this rank's particles: {e}", path.display()))?;
    if !root {
        // Rank 0 holds what the sinks read; this rank only its own part.
        sim.world.particles = sim.world.particles.select(&[]);
    }
    let result = driver.run_with(&mut sim, vec![&mut progress], signals.flag(), Some(&mut split));
    let failure = split.failure().map(str::to_string);
    let lines = split.report.lines();
    if !root {
        let ok = result.is_ok() && failure.is_none();
        return Ok((String::new(), if ok { ExitCode::SUCCESS } else { ExitCode::FAILURE }));
    }
    // Rank 0 stopped on an output error of its own while the others step on: they are told by
    // ending the whole run once every file rank 0 holds is finished (below).
    let abandoned = result.is_err();
    sim.record.stage_times = split.local().record.stage_times;
    let (mut text, code) = finish_run(driver, &sim, result, (&scene, &path, output_interval), signals);
    for line in lines {
        let _ = writeln!(text, "{line}");
    }
    if abandoned {
        print!("{text}");
        let _ = std::io::stdout().flush();
        comm.abandon(1);
    }
    if let Some(f) = failure {
        eprintln!("error: {f}");
        return Ok((text, ExitCode::FAILURE));
    }
    Ok((text, code))
}

/// A run ready to step: its scene, its driver with the files open, its progress bar and its
/// simulation.
struct Prepared {
    scene: Scene,
    driver: Driver,
    progress: Progress,
    sim: wetbounce::Simulation,
    output_interval: f64,
    /// The scene file, as the report names it.
    path: PathBuf,
}

/// Loads the scene and opens the outputs. `root`: this process writes the files (the only
/// process, or rank 0 of a run on ranks).
fn prepare_run(args: &RunArgs, (root, on_ranks): (bool, bool)) -> Result<Prepared, String> {
    let path = args.scene.as_path();
    set_threads(args.threads, on_ranks)?;
    let formats = args.formats.clone().unwrap_or_else(Format::defaults);
    for f in &formats {
        f.available().map_err(|e| format!("--formats {}: {e}", f.name()))?;
    }
    let options =
        LoadOptions { allow_long_run: args.allow_long_run, allow_large_memory: args.allow_large_memory };
    let mut scene = Scene::load_with(path, options).map_err(|e| e.to_string())?;
    let output_interval = output_interval(&scene, args)?;
    let policy = args.checkpoints.policy(&scene.checkpoint)?;
    // The scene's particles move into the simulation: a run holds one copy of them.
    let take = |scene: &mut Scene| scene.take_simulation().map_err(|e| e.to_string());
    if !root {
        let driver = Driver::new(None, &[], scene.duration, output_interval)
            .map_err(|errors| errors.iter().map(ToString::to_string).collect::<Vec<_>>().join("\nerror: "))?;
        let sim = take(&mut scene)?;
        let progress = Progress::new(scene.duration, true);
        return Ok(Prepared { scene, driver, progress, sim, output_interval, path: path.to_path_buf() });
    }
    let stem = path.file_stem().map_or("scene".into(), |s| s.to_string_lossy().into_owned());
    let out = args.out.clone().unwrap_or_else(|| Path::new("out").join(&stem));
    std::fs::create_dir_all(&out)
        .map_err(|e| format!("{}: cannot create the output folder: {e}", out.display()))?;
    check_output_size(&scene, args, &formats, output_interval, &out)?;
    if let Some(warning) = memory_warning(&scene.estimate) {
        eprintln!("warning: {warning}");
    }

    let folder = Folder {
        out: &out,
        stem: &stem,
        scene_path: &args.scene,
        scene_source: &scene.source,
        max_spheres: args.max_spheres.unwrap_or(usize::MAX),
        // Spin columns only in a scene with rotation: the others keep their files byte for byte.
        rotation: scene.setup.physics.rotation,
    };
    let saved_scene = SavedScene {
        path: std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf()),
        given: path.to_path_buf(),
        source: scene.source.clone(),
        output_interval,
        formats: formats.iter().map(|f| f.name().to_string()).collect(),
        stem: stem.clone(),
        max_spheres: args.max_spheres.unwrap_or(usize::MAX),
    };
    let checkpoints = Checkpoints::new(policy, &out.join("checkpoints"), saved_scene, 0.0);
    let driver = Driver::new(Some(&folder), &formats, scene.duration, output_interval)
        .map_err(|errors| errors.iter().map(ToString::to_string).collect::<Vec<_>>().join("\nerror: "))?;
    report_stale(driver.stale());
    // An earlier run's checkpoints would resume it over this run's files.
    for old in wetbounce::run::checkpoint::list(checkpoints.folder()) {
        if std::fs::remove_file(&old).is_ok() {
            eprintln!("note: removed {}: a checkpoint of an earlier run", old.display());
        }
    }
    let driver = driver.checkpointing(checkpoints);
    let progress = Progress::new(scene.duration, args.quiet);
    let sim = take(&mut scene)?;
    Ok(Prepared { scene, driver, progress, sim, output_interval, path: path.to_path_buf() })
}

/// Ends a run (fresh or resumed): `summary.json`, the report on standard output, the exit status.
fn finish_run(
    driver: Driver,
    sim: &wetbounce::Simulation,
    result: Result<RunReport, wetbounce::run::RunFailed>,
    (scene, path, output_interval): (&Scene, &Path, f64),
    signals: &StopSignals,
) -> (String, ExitCode) {
    let mut text = String::new();
    let checkpoints: Vec<PathBuf> = driver.checkpoints_written().to_vec();
    let signal = signals.received().map(|s| s.name);
    let Ended { report, summary, errors, written } = driver.finish(sim, result, signal);
    // The step actually taken: `dt`, or the output interval when that is shorter (a step never
    // crosses an output time).
    let step = if output_interval < scene.setup.dt {
        format!(
            "dt = {output_interval} s (the output interval; the scene's dt = {} s is longer)",
            scene.setup.dt
        )
    } else {
        format!("dt = {} s", scene.setup.dt)
    };
    let _ = writeln!(
        text,
        "{}: {} particles, {} integrator, {step}",
        path.display(),
        summary.total(),
        scene.setup.integrator.name(),
    );
    let _ = writeln!(text, "{summary}");
    for lost in &sim.record.lost {
        eprintln!("warning: particle {} became non-finite at t = {} s and was removed", lost.id, lost.time);
    }
    // A file that failed is named on standard error, not as written (`Ended::written`).
    let names: Vec<String> = written.iter().map(|p| p.display().to_string()).collect();
    let _ = writeln!(text, "wrote {}", names.join(", "));
    if let Some(last) = checkpoints.iter().rev().find(|p| p.is_file()) {
        let _ = writeln!(text, "checkpoint {} (wetbounce resume {0} goes on from it)", last.display());
    }
    (text, exit_status(&report, scene.duration, signals, &errors, sim.record.left_field.as_ref()))
}

/// The options of `resume`.
struct ResumeArgs {
    checkpoint: PathBuf,
    out: Option<PathBuf>,
    scene: Option<PathBuf>,
    formats: Option<Vec<Format>>,
    threads: Option<u16>,
    quiet: bool,
    checkpoints: CheckpointArgs,
}

fn resume_run(args: &ResumeArgs, comm: Option<&dyn Comm>) -> Result<(String, ExitCode), String> {
    let signals = StopSignals::install().map_err(|e| format!("cannot install the signal handlers: {e}"))?;
    let root = comm.is_none_or(|c| c.rank() == 0);
    drive(comm, prepare_resume(args, (root, comm.is_some())), &signals)
}

/// Reads the checkpoint and, on the process that writes the files (`root`), carries the run's
/// files and opens them where the checkpoint left them. Every rank of a run on ranks reads the
/// checkpoint (the same path on every machine).
fn prepare_resume(args: &ResumeArgs, (root, on_ranks): (bool, bool)) -> Result<Prepared, String> {
    set_threads(args.threads, on_ranks)?;
    let resumed =
        wetbounce::run::resume::resume(&args.checkpoint, args.scene.as_deref()).map_err(|e| e.to_string())?;
    let wetbounce::run::resume::Resumed { mut saved, scene, sim, .. } = resumed;
    // A new output interval (`--scene`) counts frames from the checkpoint's time on.
    if scene.output_interval != saved.scene.output_interval {
        let t = sim.world.time;
        saved.position.k = wetbounce::run::RunPosition::next_index(t, scene.output_interval);
        saved.position.at_frame = false;
        saved.scene.output_interval = scene.output_interval;
    }
    let scene_path = saved.scene.given.clone();
    let output_interval = scene.output_interval;
    if !root {
        let driver = Driver::new(None, &[], scene.duration, output_interval)
            .map_err(|errors| errors.iter().map(ToString::to_string).collect::<Vec<_>>().join("\nerror: "))?
            .from_position(saved.position);
        let progress = Progress::new(scene.duration, true);
        return Ok(Prepared { scene, driver, progress, sim, output_interval, path: scene_path });
    }
    let formats = match &args.formats {
        Some(f) => f.clone(),
        None => saved.scene.formats.iter().map(|n| Format::parse(n)).collect::<Result<_, _>>()?,
    };
    for f in &formats {
        f.available().map_err(|e| format!("--formats {}: {e}", f.name()))?;
    }
    let from = wetbounce::run::resume::run_folder(&args.checkpoint);
    let out = args.out.clone().unwrap_or_else(|| from.clone());
    wetbounce::run::resume::carry_outputs(&from, &out, &saved)
        .map_err(|e| format!("{}: cannot carry the run's files to {}: {e}", from.display(), out.display()))?;
    let stem = saved.scene.stem.clone();
    let folder = Folder {
        out: &out,
        stem: &stem,
        scene_path: &scene_path,
        scene_source: &scene.source,
        max_spheres: saved.scene.max_spheres,
        rotation: scene.setup.physics.rotation,
    };
    saved.scene.formats = formats.iter().map(|f| f.name().to_string()).collect();
    let policy = args.checkpoints.policy(&scene.checkpoint)?;
    let checkpoints = Checkpoints::new(policy, &out.join("checkpoints"), saved.scene.clone(), sim.world.time);
    let driver = Driver::resume(&folder, &formats, scene.duration, &saved)
        .map_err(|errors| errors.iter().map(ToString::to_string).collect::<Vec<_>>().join("\nerror: "))?;
    let driver = driver.checkpointing(checkpoints);
    let progress = Progress::new(scene.duration, args.quiet);
    Ok(Prepared { scene, driver, progress, sim, output_interval, path: scene_path })
}

/// How `k` ranks would split the scene at its start: the run's own split, on `k` threads of
/// this process standing in for the ranks.
fn split_report(scene: &Scene, k: usize) -> Result<Vec<String>, String> {
    let sim = scene.simulation();
    let reports: Vec<Result<SplitReport, String>> = std::thread::scope(|s| {
        let handles: Vec<_> = wetbounce::ranks::comm::Threads::set(k)
            .into_iter()
            .map(|comm| {
                let sim = &sim;
                s.spawn(move || {
                    Split::new(&comm, sim)
                        .map(|split| SplitReport { threads: 0, ..split.report.clone() })
                        .map_err(|e| e.to_string())
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap_or_else(|_| Err("a rank failed".into()))).collect()
    });
    let report = reports.into_iter().next().unwrap_or_else(|| Err("no rank".into()))?;
    let mut lines = vec![format!("on {k} ranks, at the start:")];
    lines.extend(report.lines().into_iter().map(|l| format!("  {l}")));
    let field = scene.estimate.field_bytes;
    lines.push(format!(
        "  every rank holds the walls{}: the particles are split, the rest is not",
        if field > 0.0 { format!(" and the flow field ({:.1} MB)", field / 1e6) } else { String::new() }
    ));
    Ok(lines)
}

/// `--threads N`: rayon's pool of N workers.
///
/// On ranks (`on_ranks`) the process's own thread is one of the workers: a rank steps its part
/// on that thread — the one that talks to MPI — and a parallel loop called from it then runs in
/// the pool instead of waking it from outside, which cost about 0.3 ms a step (10⁵ beads on 2
/// ranks × 1 thread: 0.70 s against 0.46 s on 1 rank × 2 threads for 1000 steps).
fn set_threads(threads: Option<u16>, on_ranks: bool) -> Result<(), String> {
    if threads.is_none() && !on_ranks {
        return Ok(());
    }
    let n = threads.map_or_else(threads_per_rank, usize::from);
    let pool = rayon::ThreadPoolBuilder::new().num_threads(n);
    let pool = if on_ranks { pool.use_current_thread() } else { pool };
    pool.build_global().map_err(|e| format!("--threads {n}: {e}"))
}

/// A rank's threads when `--threads` is not given: the machine's cores shared among the ranks
/// on it, and no more than the cores the rank may run on. (Open MPI binds each rank to a whole
/// socket beyond 2 ranks: with rayon's default, 16 ranks on 16 cores would run 256 threads.)
fn threads_per_rank() -> usize {
    let mine = std::thread::available_parallelism().map_or(1, |n| n.get());
    let local = ["OMPI_COMM_WORLD_LOCAL_SIZE", "MPI_LOCALNRANKS"]
        .iter()
        .find_map(|v| std::env::var(v).ok()?.parse::<usize>().ok())
        .unwrap_or(1)
        .max(1);
    // SAFETY: sysconf reads a system constant; it has no pointer argument.
    let online = unsafe { libc::sysconf(libc::_SC_NPROCESSORS_ONLN) };
    let online = usize::try_from(online).ok().filter(|&n| n > 0).unwrap_or(mine);
    (online / local).clamp(1, mine)
}

/// Says on standard error which outputs of an earlier run were removed (`output::stale`): left
/// beside the new outputs, an old events.csv or MCAP would be read as this run's. A file that
/// could not be removed is a warning, not a failed run.
fn report_stale(r: &wetbounce::output::stale::Removed) {
    for failed in &r.failed {
        eprintln!("warning: {failed}");
    }
    if !r.removed.is_empty() {
        let names: Vec<String> = r.removed.iter().map(|p| p.display().to_string()).collect();
        eprintln!(
            "note: removed {}: an earlier run's outputs in formats this run does not write",
            names.join(", ")
        );
    }
}

/// Reports how the run ended on standard error and picks the exit status: 1 after an output
/// error (each named, file and OS error), 128 + the signal's number after a stop signal (130
/// SIGINT, 143 SIGTERM, 129 SIGHUP), else 0.
fn exit_status(
    report: &RunReport,
    duration: f64,
    signals: &StopSignals,
    errors: &[OutputError],
    left_field: Option<&OutsideField>,
) -> ExitCode {
    if let Some(e) = left_field {
        eprintln!("error: {e}");
    }
    for e in errors {
        eprintln!("error: {e}");
    }
    let signal = signals.received();
    if report.interrupted || !errors.is_empty() {
        let cause = match (errors.first(), signal) {
            _ if left_field.is_some() => "a particle outside the flow field".to_string(),
            (Some(_), _) => "an output error".to_string(),
            (None, Some(s)) => s.name.to_string(),
            (None, None) => "a stop request".to_string(),
        };
        eprintln!(
            "interrupted: stopped at t = {:.6} s of {} s after {} steps, by {cause}; the outputs hold \
             everything up to that time",
            report.time, duration, report.steps
        );
    }
    match (errors.is_empty() && left_field.is_none(), signal) {
        (false, _) => ExitCode::FAILURE,
        (true, Some(s)) if report.interrupted => ExitCode::from(s.exit_status()),
        _ => ExitCode::SUCCESS,
    }
}

/// `wetbounce recover INPUT [OUTPUT]`.
fn recover_mcap(input: &Path, output: Option<&Path>) -> Result<String, String> {
    let output = match output {
        Some(o) => o.to_path_buf(),
        None => {
            let name = input.file_name().map_or("out".into(), |n| n.to_string_lossy().into_owned());
            let stem = name.strip_suffix(".mcap").unwrap_or(&name);
            input.with_file_name(format!("{stem}.recovered.mcap"))
        }
    };
    let r = wetbounce::output::mcap::recover(input, &output).map_err(|e| e.to_string())?;
    let last = r
        .last_log_time
        .map_or("no message".into(), |ns| format!("the last at t = {:.6} s", ns as f64 * 1e-9));
    let how = match &r.cut {
        Some(reason) => format!("the file is cut ({reason}); everything before the cut was read"),
        None => "the file was complete".into(),
    };
    Ok(format!(
        "{}: {} messages ({last}), {} metadata records; {how}\nwrote {}\n",
        input.display(),
        r.messages,
        r.metadata,
        output.display()
    ))
}

/// The output interval of a run: the scene's, or `--output-interval`, which must be a time > 0
/// and give no more frames than the scene's own interval may (unless `--allow-long-run`).
fn output_interval(scene: &Scene, args: &RunArgs) -> Result<f64, String> {
    let Some(s) = args.output_interval else { return Ok(scene.output_interval) };
    if !(s.is_finite() && s > 0.0) {
        return Err(format!("--output-interval: must be a finite time > 0 s, got {s}"));
    }
    if !args.allow_long_run {
        wetbounce::scene::run_length(scene.duration, s, scene.setup.dt)
            .map_err(|e| format!("--output-interval {s:e}: {e}"))?;
    }
    Ok(s)
}

fn check_scene(path: &Path, options: LoadOptions, ranks: Option<usize>) -> Result<String, String> {
    let mut text = String::new();
    let scene = Scene::load_with(path, options).map_err(|e| e.to_string())?;
    let _ = writeln!(text, "{}: valid", path.display());
    let _ = writeln!(
        text,
        "  {} particles, {} walls, effects [{}], integrator {}, dt = {} s, duration = {} s",
        scene.particles.len(),
        scene.setup.walls.len(),
        scene.setup.physics.effect_names.join(", "),
        scene.setup.integrator.name(),
        scene.setup.dt,
        scene.duration
    );
    if let Some(a) = &scene.auto_step {
        let _ = writeln!(
            text,
            "  dt = \"auto\", accuracy \"{}\": {} with dt = {:.4e} s = T/{:.0}, T = {:.4e} s, the {}",
            a.accuracy.name(),
            a.integrator.name(),
            a.dt,
            a.time_scale / a.dt,
            a.time_scale,
            a.limited_by
        );
        // A microsecond step from a Hertz time: usually solid beads held by a contact-time
        // effect meant for the drops beside them (issue 30, item 6).
        if a.dt < 1e-5 && a.limited_by.starts_with("contact time") {
            let _ = writeln!(
                text,
                "warning: dt = {:.3e} s comes from the {}; if only some kinds need holding at \
                 contact (drops, not solid beads), name them: contact_time = {{ kinds = [..] }}",
                a.dt, a.limited_by
            );
        }
    }
    if scene.setup.impact_location != wetbounce::contact::ImpactLocation::InStep {
        let _ = writeln!(text, "  impact location: {}", scene.setup.impact_location.name());
    }
    let rule = &scene.setup.rule;
    match rule.e_rule {
        None => {
            let _ = writeln!(
                text,
                "  bounce: beta = {}, St_c = {}, e_t = {}, hold at contact: {}",
                rule.beta, rule.st_critical, rule.tangential_restitution, rule.hold_at_contact
            );
        }
        // With wall lubrication (docs/physics.md §8): e of the impact speed, no beta, no St_c.
        Some(e) => {
            let e = e.map_or("restitution_max".to_string(), |e| e.to_string());
            let _ = writeln!(
                text,
                "  bounce: rule e (e = {e}, of the speed at impact, rebound if e St >= ln 2), e_t = {}, \
                 hold at contact: {}",
                rule.tangential_restitution, rule.hold_at_contact
            );
        }
    }
    let reports = kind_reports(&scene);
    // The kind column fits the longest name; a number too wide for its column is printed in
    // short scientific form (St ~ 4e7 for a bead in air), so the columns stay aligned.
    let kind_width = reports.iter().map(|r| r.kind.chars().count()).max().unwrap_or(0).max(12);
    let _ = writeln!(
        text,
        "  {:<kind_width$} {:>9} {:>10} {:>8} {:>8} {:>7} {:>10} {:>10} {:>8}  bounces",
        "kind", "d [mm]", "V_t [m/s]", "Re", "St", "eps", "t_c [ms]", "t_r [ms]", "t_c/t_r"
    );
    // In vacuum or without drag some time scales do not exist: print "-".
    let num = |v: f64, prec: usize, width: usize| {
        if !v.is_finite() {
            return "-".to_string();
        }
        let fixed = format!("{v:.prec$}");
        if fixed.len() <= width { fixed } else { format!("{v:.2e}") }
    };
    for r in reports {
        let _ = writeln!(
            text,
            "  {:<kind_width$} {:>9} {:>10} {:>8} {:>8} {:>7.3} {:>10} {:>10} {:>8}  {}{}",
            r.kind,
            num(r.diameter * 1e3, 4, 9),
            num(r.terminal_velocity, 4, 10),
            num(r.reynolds, 2, 8),
            num(r.stokes, 2, 8),
            r.eps,
            num(r.contact_time * 1e3, 4, 10),
            num(r.relaxation_time * 1e3, 3, 10),
            num(r.contact_time / r.relaxation_time, 4, 8),
            if r.bounces { "yes" } else { "no" },
            if r.rising { " (rises)" } else { "" }
        );
    }
    if let Some(wall) = scene.setup.walls.first() {
        let _ = writeln!(text, "  (impact at terminal velocity on wall \"{}\")", wall.name);
    }
    for line in field_report(&scene) {
        let _ = writeln!(text, "  {line}");
    }
    if let Some(k) = ranks {
        for line in split_report(&scene, k)? {
            let _ = writeln!(text, "  {line}");
        }
    }
    for line in cost_report(&scene) {
        let _ = writeln!(text, "  {line}");
    }
    Ok(text)
}

/// What `check` says a run costs: its memory, and the bytes each output format writes (from
/// counts, [`wetbounce::scene::estimate`]), with a warning for each that is large.
fn cost_report(scene: &Scene) -> Vec<String> {
    use wetbounce::scene::estimate::{OUTPUT_WARNING_BYTES, bytes, memory_breakdown};
    let e = &scene.estimate;
    let rotation = scene.setup.physics.rotation;
    let mut out = vec![
        format!("memory: about {} ({})", bytes(e.memory_bytes()), memory_breakdown(e)),
        format!(
            "output: {} frames, {} particle-frames: trajectories.csv about {}, MCAP about {}, VTK about {}",
            e.frames,
            wetbounce::scene::estimate::count(e.particle_frames),
            bytes(e.csv_bytes(rotation)),
            bytes(e.mcap_bytes()),
            bytes(e.vtk_bytes())
        ),
    ];
    out.extend(memory_warning(e).into_iter().map(|w| format!("warning: {w}")));
    let largest = e.csv_bytes(rotation).max(e.mcap_bytes()).max(e.vtk_bytes());
    if largest > OUTPUT_WARNING_BYTES {
        out.push(format!(
            "warning: the outputs may reach {} (over {}): raise simulation.output_interval, or write fewer \
             formats",
            bytes(largest),
            bytes(OUTPUT_WARNING_BYTES)
        ));
    }
    out
}

/// A warning when the run's memory is over half of what this machine has available (a run
/// over all of it is refused at load, unless `--allow-large-memory`).
fn memory_warning(e: &wetbounce::scene::estimate::RunEstimate) -> Option<String> {
    use wetbounce::scene::estimate::{available_memory, bytes};
    let available = available_memory()?;
    (e.memory_bytes() > 0.5 * available).then(|| {
        format!(
            "the run may need {} of memory, more than half the {} this machine has available",
            bytes(e.memory_bytes()),
            bytes(available)
        )
    })
}

/// Refuses a run whose outputs, in `formats` at `output_interval`, are estimated at more than
/// the free space of `out`'s file system (unless `--allow-large-output`), and warns past
/// [`wetbounce::scene::estimate::OUTPUT_WARNING_BYTES`].
fn check_output_size(
    scene: &Scene,
    args: &RunArgs,
    formats: &[Format],
    output_interval: f64,
    out: &Path,
) -> Result<(), String> {
    use wetbounce::scene::estimate::{OUTPUT_WARNING_BYTES, bytes, free_disk_space};
    let e = scene.estimate.with_output_interval(scene.duration, output_interval, &scene.estimate_inputs);
    let rotation = scene.setup.physics.rotation;
    let mut total = 0.0;
    let mut parts = Vec::new();
    for f in formats {
        let b = match f {
            Format::Csv => e.csv_bytes(rotation),
            Format::Mcap | Format::Rrd => e.mcap_bytes(),
            Format::Vtk => e.vtk_bytes(),
        };
        total += b;
        parts.push(format!("{} {}", format!("{f:?}").to_lowercase(), bytes(b)));
    }
    let what = format!(
        "{} frames of up to {} particles: about {} ({})",
        e.frames,
        wetbounce::scene::estimate::count(e.max_particles),
        bytes(total),
        parts.join(", ")
    );
    if !args.allow_large_output
        && let Some(free) = free_disk_space(out)
        && total > free
    {
        return Err(format!(
            "{}: the outputs would take {what}, more than the {} free in {}; raise \
             simulation.output_interval (or --output-interval), write fewer --formats, or allow it with \
             --allow-large-output",
            args.scene.display(),
            bytes(free),
            out.display()
        ));
    }
    if total > OUTPUT_WARNING_BYTES {
        eprintln!("warning: the outputs may take {what}");
    }
    Ok(())
}
