//! `[[injectors]]` and `[[outlets]]`: validation and building.

use super::error::Invalid;
use super::error::check::{self, only, required};
use super::error::fmt::{num, vec3};
use super::ranges::{DIAMETER, LENGTH, LENGTH_OR_ZERO, SPEED, TIME, TIME_OR_ZERO};
use super::schema::*;
use crate::particles::ParticleKind;
use crate::pipeline::inject::{Injector, Region, SizeDistribution};
use crate::pipeline::outlets::{Outlet, OutletShape};
use crate::walls::Wall;

/// Most particles the injectors of a scene may be asked for over the run, as for the initial
/// particles: a typo in a rate must not exhaust memory.
const MAX_INJECTED: f64 = 50_000_000.0;

/// How many standard deviations (of `d`, or of `ln d` for a log-normal) the truncation range
/// may lie from the centre of the distribution: beyond it the range holds so little of the
/// distribution that redrawing until a size falls inside it would not end.
const MAX_SIGMAS_AWAY: f64 = 4.0;

fn name_of(key: &str, given: &Option<String>, default: String, taken: &[String]) -> Result<String, Invalid> {
    let name = given.clone().unwrap_or(default);
    if name.trim().is_empty() {
        return Err(Invalid::new(format!("{key}.name"), "must not be empty"));
    }
    if taken.contains(&name) {
        return Err(Invalid::new(format!("{key}.name"), format!("duplicate name \"{name}\"")));
    }
    Ok(name)
}

pub(super) fn build_injectors(
    specs: &[InjectorSpec],
    kinds: &[ParticleKind],
    duration: f64,
) -> Result<Vec<Injector>, Invalid> {
    let mut out: Vec<Injector> = Vec::new();
    let mut total = 0.0;
    for (i, s) in specs.iter().enumerate() {
        let key = format!("injectors[{i}]");
        let k = |f: &str| format!("{key}.{f}");
        let taken: Vec<String> = out.iter().map(|j| j.name.clone()).collect();
        let name = name_of(&key, &s.name, key.clone(), &taken)?;
        let kind = kinds.iter().position(|x| x.name == s.kind).ok_or_else(|| {
            let names: Vec<&str> = kinds.iter().map(|x| x.name.as_str()).collect();
            Invalid::new(k("kind"), format!("unknown kind \"{}\"; kinds are: {}", s.kind, names.join(", ")))
        })? as u16;
        let rate = check::positive(&k("rate"), s.rate)?;
        let region = build_region(&k("region"), &s.region)?;
        let diameter = build_size(&k("diameter"), &s.diameter)?;
        let velocity = check::magnitude_in(&k("velocity"), s.velocity, &SPEED)?;
        let start = check::non_negative_in(&k("start"), s.start, &TIME_OR_ZERO)?;
        let stop = match s.stop {
            None => f64::INFINITY,
            Some(t) => {
                check::finite(&k("stop"), t)?;
                if t <= start {
                    return Err(Invalid::new(
                        k("stop"),
                        format!("must be > start {}, got {}", num(start), num(t)),
                    ));
                }
                TIME.check(&k("stop"), t)?
            }
        };
        total += rate * (stop.min(duration) - start).max(0.0);
        if total > MAX_INJECTED {
            return Err(Invalid::new(
                k("rate"),
                format!("asks for {total:.3e} particles over the run, more than {MAX_INJECTED:.0}"),
            ));
        }
        out.push(Injector { name, kind, rate, region, diameter, velocity, start, stop, seed: s.seed });
    }
    Ok(out)
}

fn build_region(key: &str, s: &RegionSpec) -> Result<Region, Invalid> {
    let k = |f: &str| format!("{key}.{f}");
    let present = [
        ("center", s.center.is_some()),
        ("normal", s.normal.is_some()),
        ("radius", s.radius.is_some()),
        ("min", s.min.is_some()),
        ("max", s.max.is_some()),
    ];
    match s.region {
        RegionType::Disk => {
            let what = "a disk region";
            only(key, &present, &["center", "normal", "radius"], what)?;
            let center = check::point(&k("center"), required(&k("center"), s.center, what)?)?;
            let normal = check::direction(&k("normal"), required(&k("normal"), s.normal, what)?)?;
            let radius = check::non_negative_in(
                &k("radius"),
                required(&k("radius"), s.radius, what)?,
                &LENGTH_OR_ZERO,
            )?;
            Ok(Region::disk(center, normal, radius))
        }
        RegionType::Box => {
            let what = "a box region";
            only(key, &present, &["min", "max"], what)?;
            let (min, max) = (required(&k("min"), s.min, what)?, required(&k("max"), s.max, what)?);
            let (lo, hi) = (check::point(&k("min"), min)?, check::point(&k("max"), max)?);
            if !lo.cmplt(hi).all() {
                return Err(Invalid::new(
                    k("max"),
                    format!("must exceed min on every axis, got min {}, max {}", vec3(min.0), vec3(max.0)),
                ));
            }
            Ok(Region::Box { min: lo, max: hi })
        }
    }
}

fn build_size(key: &str, s: &SizeSpec) -> Result<SizeDistribution, Invalid> {
    let k = |f: &str| format!("{key}.{f}");
    let present = [
        ("value", s.value.is_some()),
        ("mean", s.mean.is_some()),
        ("std_dev", s.std_dev.is_some()),
        ("median", s.median.is_some()),
        ("sigma", s.sigma.is_some()),
        ("min", s.min.is_some()),
        ("max", s.max.is_some()),
    ];
    let range = |what: &str| -> Result<(f64, f64), Invalid> {
        let min = check::positive_in(&k("min"), required(&k("min"), s.min, what)?, &DIAMETER)?;
        let max = check::positive_in(&k("max"), required(&k("max"), s.max, what)?, &DIAMETER)?;
        if max <= min {
            return Err(Invalid::new(k("max"), format!("must be > min {}, got {}", num(min), num(max))));
        }
        Ok((min, max))
    };
    // The truncation range must overlap the bulk of the distribution (centre c, spread w).
    let reachable = |c: f64, w: f64, lo: f64, hi: f64| -> Result<(), Invalid> {
        if hi < c - MAX_SIGMAS_AWAY * w || lo > c + MAX_SIGMAS_AWAY * w {
            Err(Invalid::new(
                k("min"),
                format!(
                    "the range [min, max] lies more than {MAX_SIGMAS_AWAY} standard deviations from the \
                     centre of the distribution, so almost no size falls in it"
                ),
            ))
        } else {
            Ok(())
        }
    };
    Ok(match s.distribution {
        SizeType::Fixed => {
            let what = "a fixed diameter";
            only(key, &present, &["value"], what)?;
            SizeDistribution::Fixed(check::positive_in(
                &k("value"),
                required(&k("value"), s.value, what)?,
                &DIAMETER,
            )?)
        }
        SizeType::Uniform => {
            let what = "a uniform distribution";
            only(key, &present, &["min", "max"], what)?;
            let (min, max) = range(what)?;
            SizeDistribution::Uniform { min, max }
        }
        SizeType::Normal => {
            let what = "a normal distribution";
            only(key, &present, &["mean", "std_dev", "min", "max"], what)?;
            let mean = check::positive_in(&k("mean"), required(&k("mean"), s.mean, what)?, &DIAMETER)?;
            let std_dev =
                check::positive_in(&k("std_dev"), required(&k("std_dev"), s.std_dev, what)?, &LENGTH)?;
            let (min, max) = range(what)?;
            reachable(mean, std_dev, min, max)?;
            SizeDistribution::Normal { mean, std_dev, min, max }
        }
        SizeType::LogNormal => {
            let what = "a log-normal distribution";
            only(key, &present, &["median", "sigma", "min", "max"], what)?;
            let median =
                check::positive_in(&k("median"), required(&k("median"), s.median, what)?, &DIAMETER)?;
            let sigma = check::positive(&k("sigma"), required(&k("sigma"), s.sigma, what)?)?;
            let (min, max) = range(what)?;
            reachable(median.ln(), sigma, min.ln(), max.ln())?;
            SizeDistribution::LogNormal { median, sigma, min, max }
        }
    })
}

pub(super) fn build_outlets(specs: &[OutletSpec], walls: &[Wall]) -> Result<Vec<Outlet>, Invalid> {
    let mut out: Vec<Outlet> = Vec::new();
    for (i, s) in specs.iter().enumerate() {
        let key = format!("outlets[{i}]");
        let k = |f: &str| format!("{key}.{f}");
        let taken: Vec<String> = out.iter().map(|o| o.name.clone()).collect();
        let name = name_of(&key, &s.name, key.clone(), &taken)?;
        let present =
            [("point", s.point.is_some()), ("normal", s.normal.is_some()), ("wall", s.wall.is_some())];
        let shape = match s.outlet {
            OutletType::Plane => {
                let what = "a plane outlet";
                only(&key, &present, &["point", "normal"], what)?;
                OutletShape::Plane {
                    point: check::point(&k("point"), required(&k("point"), s.point, what)?)?,
                    normal: check::direction(&k("normal"), required(&k("normal"), s.normal, what)?)?,
                }
            }
            OutletType::Wall => {
                let what = "a wall outlet";
                only(&key, &present, &["wall"], what)?;
                let wall = required(&k("wall"), s.wall.as_ref(), what)?;
                let index = walls.iter().position(|w| &w.name == wall).ok_or_else(|| {
                    let names: Vec<&str> = walls.iter().map(|w| w.name.as_str()).collect();
                    Invalid::new(
                        k("wall"),
                        format!("unknown wall \"{wall}\"; walls are: {}", names.join(", ")),
                    )
                })?;
                OutletShape::Wall(index as u32)
            }
        };
        out.push(Outlet { name, shape });
    }
    Ok(out)
}
