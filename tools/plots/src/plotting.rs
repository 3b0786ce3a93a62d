//! What the plotting programs share: the font, and drawing one figure as PNG and SVG.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::{FontStyle, register_font};
use std::path::Path;

/// DejaVu Sans, as Debian installs it (the same font as `plot_paths`): loaded at run time so
/// that nothing links a system library.
pub const DEFAULT_FONT: &str = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

/// Takes `--font FILE` out of `args`: the file, or [`DEFAULT_FONT`] without the flag; an error
/// when the flag has no file after it.
pub fn take_font_arg(args: &mut Vec<String>) -> Result<std::path::PathBuf, String> {
    let Some(k) = args.iter().position(|a| a == "--font") else {
        return Ok(DEFAULT_FONT.into());
    };
    if k + 1 >= args.len() {
        return Err("--font needs a file".into());
    }
    let font = args.remove(k + 1).into();
    args.remove(k);
    Ok(font)
}

/// Registers `font` (a TrueType file) as plotters' "sans-serif".
pub fn register(font: &Path) -> Result<(), String> {
    let bytes = std::fs::read(font).map_err(|e| format!("{}: {e}", font.display()))?;
    // plotters keeps the font for the life of the program.
    register_font("sans-serif", FontStyle::Normal, Box::leak(bytes.into_boxed_slice()))
        .map_err(|_| format!("{}: not a TrueType font", font.display()))
}

/// The result of a drawing function.
pub type Drawn = Result<(), Box<dyn std::error::Error>>;

/// Draws the same figure into `STEM.png` and `STEM.svg`.
pub fn png_and_svg(
    stem: &Path,
    size: (u32, u32),
    draw_png: impl Fn(DrawingArea<BitMapBackend, Shift>) -> Drawn,
    draw_svg: impl Fn(DrawingArea<SVGBackend, Shift>) -> Drawn,
) -> Result<(), String> {
    let png = stem.with_extension("png");
    let svg = stem.with_extension("svg");
    draw_png(BitMapBackend::new(&png, size).into_drawing_area())
        .map_err(|e| format!("{}: {e}", png.display()))?;
    draw_svg(SVGBackend::new(&svg, size).into_drawing_area())
        .map_err(|e| format!("{}: {e}", svg.display()))?;
    Ok(())
}

/// A colour per line, readable on white.
pub const PALETTE: [RGBColor; 6] = [
    RGBColor(0x1f, 0x77, 0xb4),
    RGBColor(0xd6, 0x27, 0x28),
    RGBColor(0x2c, 0xa0, 0x2c),
    RGBColor(0xff, 0x7f, 0x0e),
    RGBColor(0x94, 0x67, 0xbd),
    RGBColor(0x8c, 0x56, 0x4b),
];

/// Draws a chart's legend: framed, on white, at `position`, labels at `font_size`.
pub fn legend<'a, DB, CT>(
    chart: &mut ChartContext<'a, DB, CT>,
    position: SeriesLabelPosition,
    font_size: u32,
) -> Drawn
where
    DB: DrawingBackend + 'a,
    DB::ErrorType: 'static,
    CT: plotters::coord::CoordTranslate,
{
    chart
        .configure_series_labels()
        .position(position)
        .background_style(WHITE)
        .border_style(BLACK)
        .label_font(("sans-serif", font_size))
        .draw()?;
    Ok(())
}

/// The `main` of a program that draws into a folder: `[OUT_DIR] [--font FILE.ttf]`, `default`
/// without a folder; the font registered, then `run(out)`; an error printed and a failure
/// status. (Each program includes this module; the ones that write elsewhere do not call it.)
#[allow(dead_code)]
pub fn main_writing_into(
    default: &str,
    run: impl FnOnce(&Path) -> Result<(), String>,
) -> std::process::ExitCode {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let result = take_font_arg(&mut args).and_then(|font| {
        register(&font)?;
        // Tools write into `out/` unless told otherwise: the committed figures in docs/ change
        // only when a user names that folder.
        let out = Path::new(args.first().map_or(default, |s| s.as_str()));
        std::fs::create_dir_all(out)
            .map_err(|e| format!("{}: cannot create the folder: {e}", out.display()))?;
        run(out)
    });
    match result {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            std::process::ExitCode::FAILURE
        }
    }
}
