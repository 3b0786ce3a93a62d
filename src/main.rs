//! The `wetbounce` command line: `run` a scene, or `check` it.

use clap::{Parser, Subcommand};
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::AtomicBool;
use wetbounce::output::{EventCsv, Sink, Statistics, TrajectoryCsv};
use wetbounce::particles::State;
use wetbounce::pipeline::run::run;
use wetbounce::scene::{Scene, kind_reports};

/// Particles and drops bouncing on walls in a viscous fluid (Legendre et al. 2006).
#[derive(Parser)]
#[command(version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run a scene; writes DIR/trajectories.csv and DIR/events.csv.
    Run {
        /// The scene file (TOML).
        scene: PathBuf,
        /// Output folder [default: out/<scene file stem>/].
        #[arg(long)]
        out: Option<PathBuf>,
        /// Worker threads [default: all cores]. Results do not depend on it.
        #[arg(long, value_parser = clap::value_parser!(u16).range(1..))]
        threads: Option<u16>,
    },
    /// Validate a scene and print each particle kind's time scales and bounce regime.
    Check {
        /// The scene file (TOML).
        scene: PathBuf,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Run {
            scene,
            out,
            threads,
        } => run_scene(&scene, out, threads),
        Command::Check { scene } => check_scene(&scene),
    };
    match result {
        Ok(text) => {
            // Reading only the head of the output (`| head`) closes the pipe: not an error.
            let mut stdout = std::io::stdout().lock();
            match stdout
                .write_all(text.as_bytes())
                .and_then(|()| stdout.flush())
            {
                Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
                    eprintln!("error: cannot write to standard output: {e}");
                    ExitCode::FAILURE
                }
                _ => ExitCode::SUCCESS,
            }
        }
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
    }
}

fn run_scene(path: &Path, out: Option<PathBuf>, threads: Option<u16>) -> Result<String, String> {
    let mut text = String::new();
    if let Some(n) = threads {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n as usize)
            .build_global()
            .map_err(|e| format!("--threads {n}: {e}"))?;
    }
    let scene = Scene::load(path).map_err(|e| e.to_string())?;
    let out = out.unwrap_or_else(|| {
        let stem = path
            .file_stem()
            .map_or("scene".into(), |s| s.to_string_lossy().into_owned());
        Path::new("out").join(stem)
    });
    std::fs::create_dir_all(&out)
        .map_err(|e| format!("{}: cannot create the output folder: {e}", out.display()))?;
    let mut trajectories =
        TrajectoryCsv::create(out.join("trajectories.csv")).map_err(|e| e.to_string())?;
    let mut events = EventCsv::create(out.join("events.csv")).map_err(|e| e.to_string())?;
    let mut stats = Statistics::default();
    let mut sim = scene.simulation();
    let stop = AtomicBool::new(false);
    let report = {
        let mut sinks: [&mut dyn Sink; 3] = [&mut trajectories, &mut events, &mut stats];
        run(
            &mut sim,
            scene.duration,
            scene.output_interval,
            &mut sinks,
            &stop,
        )
        .map_err(|e| e.to_string())?
    };
    let count = |s: State| sim.particles.state.iter().filter(|&&x| x == s).count();
    let _ = writeln!(
        text,
        "{}: {:.6} s simulated in {} steps, {:.3} s wall time ({} particles, {} integrator)",
        path.display(),
        report.time,
        report.steps,
        report.wall_time.as_secs_f64(),
        sim.particles.len(),
        scene.integrator.name()
    );
    let _ = writeln!(text, "{stats}");
    let _ = writeln!(
        text,
        "at the end: {} free, {} held, {} resting; {} lost to non-finite state",
        count(State::Free),
        count(State::Held),
        count(State::Resting),
        sim.lost.len()
    );
    for lost in &sim.lost {
        eprintln!(
            "warning: particle {} became non-finite at t = {} s and was removed",
            lost.id, lost.time
        );
    }
    let _ = writeln!(
        text,
        "wrote {} and {}",
        out.join("trajectories.csv").display(),
        out.join("events.csv").display()
    );
    Ok(text)
}

fn check_scene(path: &Path) -> Result<String, String> {
    let mut text = String::new();
    let scene = Scene::load(path).map_err(|e| e.to_string())?;
    let _ = writeln!(text, "{}: valid", path.display());
    let _ = writeln!(
        text,
        "  {} particles, {} walls, effects [{}], integrator {}, dt = {} s, duration = {} s",
        scene.particles.len(),
        scene.walls.len(),
        scene.physics.effect_names.join(", "),
        scene.integrator.name(),
        scene.dt,
        scene.duration
    );
    let _ = writeln!(
        text,
        "  bounce: beta = {}, St_c = {}, e_t = {}, hold at contact: {}",
        scene.rule.beta,
        scene.rule.st_critical,
        scene.rule.tangential_restitution,
        scene.rule.hold_at_contact
    );
    let _ = writeln!(
        text,
        "  {:<12} {:>9} {:>10} {:>8} {:>8} {:>7} {:>10} {:>10} {:>8}  bounces",
        "kind", "d [mm]", "V_t [m/s]", "Re", "St", "eps", "t_c [ms]", "t_r [ms]", "t_c/t_r"
    );
    // In vacuum or without drag some time scales do not exist: print "-".
    let num = |v: f64, prec: usize| {
        if v.is_finite() {
            format!("{v:.prec$}")
        } else {
            "-".into()
        }
    };
    for r in kind_reports(&scene) {
        let _ = writeln!(
            text,
            "  {:<12} {:>9.4} {:>10} {:>8} {:>8} {:>7.3} {:>10} {:>10} {:>8}  {}{}",
            r.kind,
            r.diameter * 1e3,
            num(r.terminal_velocity, 4),
            num(r.reynolds, 2),
            num(r.stokes, 2),
            r.eps,
            num(r.contact_time * 1e3, 4),
            num(r.relaxation_time * 1e3, 3),
            num(r.contact_time / r.relaxation_time, 4),
            if r.bounces { "yes" } else { "no" },
            if r.rising { " (rises)" } else { "" }
        );
    }
    if let Some(wall) = scene.walls.first() {
        let _ = writeln!(
            text,
            "  (impact at terminal velocity on wall \"{}\")",
            wall.name
        );
    }
    Ok(text)
}
