//! Prints docs/physics.md §6: each number quoted in L06 beside what the engine's correlations give.
//!
//! Run: `cargo run --release --bin paper_table`.

use wetbounce::correlations::*;

fn main() {
    let g = 9.81;
    let water25 = (997.0, 0.89e-3);
    let water20 = (998.2, 1.002e-3);
    let sn = drag_factor_schiller_naumann;
    println!("{:<58} {:>12} {:>12}", "case (docs/physics.md §6)", "L06 quotes", "engine");
    let row = |case: &str, quoted: &str, engine: String| println!("{case:<58} {quoted:>12} {engine:>12}");

    let t = hertz_contact_time(15_250.0, 650e9, 0.23, 205e9, 0.295, 8e-3, 0.198);
    row("WC bead 8 mm on steel at 19.8 cm/s, Hertz t (eq. 3)", "43 µs", format!("{:.1} µs", t * 1e6));

    for (d, st_quoted) in [(2.5e-3, "32"), (2.75e-3, "38")] {
        let tv = terminal_velocity(860.0, water25.0, d, water25.1, g, sn);
        let st = stokes_number(860.0, water25.0, tv.speed, d, water25.1);
        row(&format!("toluene drop {} mm in water 25 °C: St", d * 1e3), st_quoted, format!("{st:.1}"));
    }
    let d = 2.5e-3;
    let tv = terminal_velocity(860.0, water25.0, d, water25.1, g, sn);
    let tr = relaxation_time(860.0, water25.0, 0.5, d, water25.1, sn(tv.reynolds));
    row("toluene drop 2.5 mm: t_r (eq. 6)", "76 ms", format!("{:.1} ms", tr * 1e3));
    let tc = drop_contact_time(860.0, water25.0, d, 0.026);
    row("toluene drop 2.5 mm: t_c (eq. 5)", "21 ms", format!("{:.1} ms", tc * 1e3));

    let tv = terminal_velocity(860.0, water25.0, 2.75e-3, water25.1, g, sn);
    let st = stokes_number(860.0, water25.0, tv.speed, 2.75e-3, water25.1);
    let eps = restitution(st, 0.91, 35.0, 10.0).value();
    row(
        "toluene drop 2.75 mm: energy lost at 1st impact (ε_max 0.91)",
        "80–90 %",
        format!("{:.1} %", 100.0 * (1.0 - eps * eps)),
    );

    let tv = terminal_velocity(2540.0, water20.0, d, water20.1, g, sn);
    let st = stokes_number(2540.0, water20.0, tv.speed, d, water20.1);
    let tr = relaxation_time(2540.0, water20.0, 0.5, d, water20.1, sn(tv.reynolds));
    row("glass sphere 2.5 mm in water 20 °C: V_t", "33 cm/s", format!("{:.1} cm/s", tv.speed * 100.0));
    row("glass sphere 2.5 mm in water 20 °C: St", "296", format!("{st:.0}"));
    row("glass sphere 2.5 mm in water 20 °C: t_r (eq. 6)", "0.7 s", format!("{:.0} ms", tr * 1e3));
    println!(
        "\nWhere the two columns differ, docs/physics.md §6 explains why the formulas, not the quotes, are right."
    );
}
