//! The `wetbounce` command line: `run` a scene, or `check` it.

use clap::{Parser, Subcommand};
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
        Ok(code) => code,
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
    }
}

fn run_scene(path: &Path, out: Option<PathBuf>, threads: Option<u16>) -> Result<ExitCode, String> {
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
    println!(
        "{}: {:.6} s simulated in {} steps, {:.3} s wall time ({} particles, {} integrator)",
        path.display(),
        report.time,
        report.steps,
        report.wall_time.as_secs_f64(),
        sim.particles.len(),
        scene.integrator.name()
    );
    println!("{stats}");
    println!(
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
    println!(
        "wrote {} and {}",
        out.join("trajectories.csv").display(),
        out.join("events.csv").display()
    );
    Ok(ExitCode::SUCCESS)
}

fn check_scene(path: &Path) -> Result<ExitCode, String> {
    let scene = Scene::load(path).map_err(|e| e.to_string())?;
    println!("{}: valid", path.display());
    println!(
        "  {} particles, {} walls, effects [{}], integrator {}, dt = {} s, duration = {} s",
        scene.particles.len(),
        scene.walls.len(),
        scene.physics.effect_names.join(", "),
        scene.integrator.name(),
        scene.dt,
        scene.duration
    );
    println!(
        "  bounce: beta = {}, St_c = {}, e_t = {}, hold at contact: {}",
        scene.rule.beta,
        scene.rule.st_critical,
        scene.rule.tangential_restitution,
        scene.rule.hold_at_contact
    );
    println!(
        "  {:<12} {:>9} {:>10} {:>8} {:>8} {:>7} {:>10} {:>10} {:>8}  bounces",
        "kind", "d [mm]", "V_t [m/s]", "Re", "St", "eps", "t_c [ms]", "t_r [ms]", "t_c/t_r"
    );
    for r in kind_reports(&scene) {
        println!(
            "  {:<12} {:>9.4} {:>10.4} {:>8.2} {:>8.2} {:>7.3} {:>10.4} {:>10.3} {:>8.4}  {}{}",
            r.kind,
            r.diameter * 1e3,
            r.terminal_velocity,
            r.reynolds,
            r.stokes,
            r.eps,
            r.contact_time * 1e3,
            r.relaxation_time * 1e3,
            r.contact_time / r.relaxation_time,
            if r.bounces { "yes" } else { "no" },
            if r.rising { " (rises)" } else { "" }
        );
    }
    if let Some(wall) = scene.walls.first() {
        println!("  (impact at terminal velocity on wall \"{}\")", wall.name);
    }
    Ok(ExitCode::SUCCESS)
}
