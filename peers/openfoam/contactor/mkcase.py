#!/usr/bin/env python3
"""OpenFOAM v1912 case of scenes/contactor.toml's drops in the contactor's computed water flow.

    python3 mkcase.py mesh CASE [CELL]       # CASE/system/blockMeshDict (and the rest of the case)
    python3 mkcase.py field CASE VTI         # CASE/0/U from CASE/0/C (postProcess writeCellCentres)
    python3 mkcase.py drops CASE DROPS.csv [E] [END]   # the cloud: one manualInjection per drop
    python3 mkcase.py reached CASE DROPS.csv # each drop's residence time from patchPostProcessing
    python3 mkcase.py compare DROPS.csv OF.csv WB_LABEL OF_LABEL   # both distributions

The mesh is tools/cfd/make_blockmesh.py's 5-degree axisymmetric wedge of the column, with the
top at the scene's outlet (z = 0.40 m) instead of the CFD's inlet (0.42): a drop that reaches
the top patch leaves the case there, and patchPostProcessing records the step it left in. The
water's velocity is not solved here: it is the table the engine reads (scenes/fields/
contactor_rz.vti, the converged simpleFoam solution of tools/cfd/case on a 0.25 mm (r, z) grid)
interpolated bilinearly at the cell centres, as the engine interpolates it at a drop's centre.
In the wedge, v1912 keeps a parcel's velocity and displacement in the x-z plane (the wedge's
centre plane, solutionD), which is exact for a drop in an axisymmetric flow with no swirl: it
stays in its meridional plane. A drop born at (x, y, z) in the engine starts at (r, 0, z).
Water: rho 997 kg/m3 (psiThermo, perfectGas with W = 1, T = 1 K, p = 997 RR), mu 0.89e-3 Pa s.
Dependencies: python3 and numpy.
"""
import base64
import csv
import importlib.util
import math
import os
import re
import struct
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", "..", ".."))
Z_OUTLET = 0.40           # scenes/contactor.toml [[outlets]] top
RHO, MU = 997.0, 0.89e-3  # water, as the scene
RR = 8314.47006650545     # v1912's universal gas constant, J/(kmol K)
RHO_P = 860.0             # toluene
DT = 1e-3                 # the scene's dt
WALLS = "(shell|doughnut_.*|disc_.*)"


def hdr(cls, obj):
    return ("FoamFile\n{\n    version     2.0;\n    format      ascii;\n"
            f"    class       {cls};\n    object      {obj};\n}}\n\n")


def write(path, text):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write(text)


def boundary(walls, inout):
    return ("boundaryField\n{\n"
            f"    \"{WALLS}\" {{ {walls} }}\n"
            f"    \"(inlet|outlet)\" {{ {inout} }}\n"
            "    axis { type empty; }\n"
            "    \"(front|back)\" { type wedge; }\n}\n")


def mesh(case, cell):
    spec = importlib.util.spec_from_file_location("make_blockmesh", os.path.join(ROOT, "tools", "cfd", "make_blockmesh.py"))
    mb = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mb)
    mb.Z_TOP = Z_OUTLET   # the drops' outlet is the top of this case
    os.makedirs(os.path.join(case, "system"), exist_ok=True)
    sys.argv = ["make_blockmesh.py", str(cell), os.path.join(case, "system", "blockMeshDict")]
    mb.main()
    control(case, 14.0)
    write(os.path.join(case, "system", "fvSchemes"), hdr("dictionary", "fvSchemes") + """\
// Only what the cloud needs: DUcDt = ddt(U) + (U & grad(U)) for virtualMass and pressureGradient
ddtSchemes           { default Euler; }
gradSchemes          { default Gauss linear; }
divSchemes           { default none; }
laplacianSchemes     { default none; }
interpolationSchemes { default linear; }
snGradSchemes        { default corrected; }
""")
    write(os.path.join(case, "system", "fvSolution"), hdr("dictionary", "fvSolution") + "solvers {}\n")
    p = RHO * RR
    write(os.path.join(case, "0", "p"), hdr("volScalarField", "p") +
          f"dimensions [1 -1 -2 0 0 0 0];\ninternalField uniform {p:.10f};\n" +
          boundary("type zeroGradient;", "type zeroGradient;"))
    write(os.path.join(case, "0", "T"), hdr("volScalarField", "T") +
          "// T = 1 K: rho = p W/(RR T) = 997 with W = 1, and the unit field WenYuDrag takes as its\n"
          "// carrier volume fraction (alphac = 1: exactly Schiller-Naumann)\n"
          "dimensions [0 0 0 1 0 0 0];\ninternalField uniform 1;\n" +
          boundary("type zeroGradient;", "type zeroGradient;"))
    write(os.path.join(case, "0", "U"), hdr("volVectorField", "U") +
          "dimensions [0 1 -1 0 0 0 0];\ninternalField uniform (0 0 0);\n" +
          boundary("type noSlip;", "type zeroGradient;"))
    write(os.path.join(case, "constant", "thermophysicalProperties"), hdr("dictionary", "thermophysicalProperties") + f"""\
thermoType
{{
    type            hePsiThermo;
    mixture         pureMixture;
    transport       const;
    thermo          hConst;
    equationOfState perfectGas;
    specie          specie;
    energy          sensibleInternalEnergy;
}}
mixture
{{
    specie          {{ molWeight 1; }}
    thermodynamics  {{ Cp 4180; Hf 0; }}
    transport       {{ mu {MU}; Pr 7; }}
}}
""")
    write(os.path.join(case, "constant", "turbulenceProperties"),
          hdr("dictionary", "turbulenceProperties") + "simulationType laminar;\n")
    write(os.path.join(case, "constant", "g"), hdr("uniformDimensionedVectorField", "g") +
          "dimensions [0 1 -2 0 0 0 0];\nvalue (0 0 -9.81);\n")


def control(case, end):
    nsteps = round(end / DT)
    write(os.path.join(case, "system", "controlDict"), hdr("dictionary", "controlDict") + f"""\
application     uncoupledKinematicParcelFoam;
startFrom       startTime;
startTime       0;
stopAt          endTime;
endTime         {end};
deltaT          {DT};
writeControl    timeStep;
writeInterval   {nsteps};
purgeWrite      0;
writeFormat     ascii;
writePrecision  12;
writeCompression off;
timeFormat      general;
timePrecision   10;
runTimeModifiable no;
""")


def read_vti(path):
    """(r0, dr, nr, z0, dz, nz, u) with u[k, i] = (u_r, u_z) at r0 + i dr, z0 + k dz."""
    text = open(path, "rb").read().decode("ascii")
    ext = [int(v) for v in re.search(r'WholeExtent="([^"]+)"', text).group(1).split()]
    origin = [float(v) for v in re.search(r'Origin="([^"]+)"', text).group(1).split()]
    spacing = [float(v) for v in re.search(r'Spacing="([^"]+)"', text).group(1).split()]
    m = re.search(r'Name="U_rz"[^>]*format="binary"[^>]*>\s*([A-Za-z0-9+/=\s]+?)\s*</DataArray>', text)
    raw = base64.b64decode("".join(m.group(1).split()))
    n = struct.unpack("<I", raw[:4])[0]
    nr, nz = ext[1] - ext[0] + 1, ext[5] - ext[4] + 1
    u = np.frombuffer(raw[4:4 + n], dtype="<f4").astype(float).reshape(nz, nr, 2)
    return origin[0], spacing[0], nr, origin[2], spacing[2], nz, u


def read_vectors(path):
    text = open(path).read()
    m = re.search(r"internalField\s+nonuniform\s+List<vector>\s*(\d+)\s*\(", text)
    n = int(m.group(1))
    body = text[m.end():]
    nums = re.findall(r"\(([^()]*)\)", body[: body.find("\n)")])
    v = np.array([[float(a) for a in s.split()] for s in nums[:n]])
    assert v.shape == (n, 3), path
    return v


def field(case, vti):
    c = read_vectors(os.path.join(case, "0", "C"))
    r0, dr, nr, z0, dz, nz, u = read_vti(vti)
    r = np.hypot(c[:, 0], c[:, 1])
    # Bilinear in (r, z), clamped to the table, as the engine does for an axisymmetric field.
    fr = np.clip((r - r0) / dr, 0, nr - 1 - 1e-9)
    fz = np.clip((c[:, 2] - z0) / dz, 0, nz - 1 - 1e-9)
    i, k = fr.astype(int), fz.astype(int)
    a, b = (fr - i)[:, None], (fz - k)[:, None]
    urz = ((1 - a) * (1 - b) * u[k, i] + a * (1 - b) * u[k, i + 1] + (1 - a) * b * u[k + 1, i] + a * b * u[k + 1, i + 1])
    # Below the table (the CFD's outlet extension, z < 0) the field is the value at z = 0; no
    # drop goes there.
    with np.errstate(invalid="ignore", divide="ignore"):
        cx = np.where(r > 1e-12, c[:, 0] / r, 0.0)
        cy = np.where(r > 1e-12, c[:, 1] / r, 0.0)
    U = np.stack([urz[:, 0] * cx, urz[:, 0] * cy, urz[:, 1]], axis=1)
    lines = "\n".join(f"({x:.8g} {y:.8g} {z:.8g})" for x, y, z in U)
    write(os.path.join(case, "0", "U"), hdr("volVectorField", "U") +
          f"// {os.path.basename(vti)} interpolated bilinearly in (r, z) at the cell centres\n"
          f"dimensions [0 1 -1 0 0 0 0];\ninternalField nonuniform List<vector>\n{len(U)}\n(\n{lines}\n)\n;\n" +
          boundary("type noSlip;", "type zeroGradient;"))
    print(f"U: {len(U)} cells, |u| max {np.abs(U).max():.4g} m/s")


def drops_of(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def drops(case, drops_csv, e, end):
    rows = drops_of(drops_csv)
    models = []
    for k, d in enumerate(rows):
        x, y, z = float(d["x"]), float(d["y"]), float(d["z"])
        name = f"drop{k:05d}"
        write(os.path.join(case, "constant", name), hdr("vectorField", name) +
              f"(\n({math.hypot(x, y):.9e} 0 {z:.9e})\n)\n")
        # SOI a microsecond before the engine's birth time: v1912 injects a manualInjection
        # parcel in the step whose start is at or before SOI (an SOI exactly on a step's start
        # can miss it by round-off), and moves it over the rest of that step (1 us).
        soi = float(d["born"]) - 1e-6
        models.append(f"""        {name}
        {{
            type manualInjection; massTotal 0; parcelBasisType fixed; nParticle 1;
            SOI {soi:.9f}; positionsFile "{name}"; U0 (0 0 0);
            sizeDistribution {{ type fixedValue; fixedValueDistribution {{ value {float(d["diameter"]):.9e}; }} }}
        }}""")
    write(os.path.join(case, "constant", "kinematicCloudProperties"), hdr("dictionary", "kinematicCloudProperties") + f"""\
solution
{{
    active          true;
    coupled         false;      // one-way, as the engine: the drops do not act on the water
    transient       yes;
    cellValueSourceCorrection off;
    maxCo           1;
    interpolationSchemes
    {{
        rho         cell;       // uniform
        thermo:mu   cell;       // uniform
        U           cellPoint;  // linear in each tet of the cell, from cell and point values
        DUcDt       cell;       // each force builds its own DUcDt field every step: the dominant cost
    }}
    integrationSchemes {{ U analytical; }}
}}
constantProperties {{ rho0 {RHO_P}; }}
subModels
{{
    particleForces
    {{
        WenYuDrag {{ alphac T; }}     // alphac = 1: Schiller-Naumann, as the scene's drag
        gravity;                      // m g (1 - rho_c/rho_p): gravity + buoyancy
        virtualMass {{ Cvm 0.5; }}    // added mass, C_M = 1/2: C_M rho_c V (DUc/Dt - dv/dt)
        pressureGradient {{ U U; }}   // rho_c V DUc/Dt; with virtualMass's part: the engine's
                                      // fluid_acceleration, (1 + C_M) rho_c V Du/Dt
    }}
    injectionModels
    {{
{chr(10).join(models)}
    }}
    dispersionModel          none;
    patchInteractionModel    standardWallInteraction;
    standardWallInteractionCoeffs
    {{
        type    rebound;
        e       {e};             // constant restitution (the scene's restitution_max)
        mu      0;               // no tangential loss
    }}
    surfaceFilmModel         none;
    stochasticCollisionModel none;
}}
cloudFunctions
{{
    reached
    {{
        type                patchPostProcessing;
        maxStoredParcels    100000000;
        patches             (inlet);   // the top, z = {Z_OUTLET}: the scene's outlet
    }}
}}
""")
    control(case, end)
    print(f"{len(rows)} drops, e = {e}, {round(end / DT)} steps of {DT} s")


def reached(case, drops_csv):
    """Prints one line per drop: index, born, residence time in OpenFOAM (its age when it hit
    the top; empty if it did not reach it), from the patchPostProcessing file of the last time."""
    rows = drops_of(drops_csv)
    base = os.path.join(case, "postProcessing", "lagrangian", "kinematicCloud", "reached")
    times = sorted(os.listdir(base), key=float) if os.path.isdir(base) else []
    path = os.path.join(base, times[-1], "inlet.post") if times else os.devnull  # none reached
    hit = {}
    with open(path) as f:
        header = None
        for line in f:
            if line.startswith("#"):
                header = line[1:].split()
                continue
            v = line.split()
            if not v:
                continue
            rec = dict(zip(header, v)) if header and len(header) == len(v) else None
            # columns: the step's end time, then the parcel's fields; origId is its injection
            # order, age the time since its injection to the hit (within the step)
            if not rec or "origId" not in rec or "age" not in rec:
                raise SystemExit(f"{path}: no origId or age column in {header}")
            hit[int(rec["origId"])] = float(rec["age"])
    # origId counts parcels in injection order, i.e. in birth order (ties keep the models' order)
    order = sorted(range(len(rows)), key=lambda k: (float(rows[k]["born"]), k))
    for oid, k in enumerate(order):
        age = hit.get(oid)
        print(f"{k},{float(rows[k]['born']):.6f},{'' if age is None else f'{age:.6f}'}")


def nearest_rank(v, q):
    """The smallest value with at least q n values at or below it (as the engine's summary)."""
    return v[max(0, math.ceil(q * len(v)) - 1)]


def compare(drops_csv, of_csv, wb_label, of_label):
    """Prints both residence-time distributions: count reached, mean, p10, p50, p90, max."""
    rows = drops_of(drops_csv)
    wb = sorted(float(r["residence"]) for r in rows if r["residence"])
    with open(of_csv) as f:
        of = sorted(float(line.split(",")[2]) for line in f if line.strip().split(",")[2:] != [""])
    print(f"{'code':<34} {'drops':>5} {'reached':>7} {'mean_s':>7} {'p10_s':>7} {'p50_s':>7} {'p90_s':>7} {'max_s':>7}")
    for label, v in ((wb_label, wb), (of_label, of)):
        if v:
            print(f"{label:<34} {len(rows):>5} {len(v):>7} {sum(v) / len(v):>7.3f} {nearest_rank(v, 0.1):>7.3f} "
                  f"{nearest_rank(v, 0.5):>7.3f} {nearest_rank(v, 0.9):>7.3f} {v[-1]:>7.3f}")
        else:
            print(f"{label:<34} {len(rows):>5} {0:>7}")


if __name__ == "__main__":
    cmd = sys.argv[1] if len(sys.argv) > 1 else ""
    if cmd == "mesh":
        mesh(sys.argv[2], float(sys.argv[3]) if len(sys.argv) > 3 else 0.0005)
    elif cmd == "field":
        field(sys.argv[2], sys.argv[3])
    elif cmd == "drops":
        drops(sys.argv[2], sys.argv[3], float(sys.argv[4]) if len(sys.argv) > 4 else 0.91,
              float(sys.argv[5]) if len(sys.argv) > 5 else 14.0)
    elif cmd == "compare":
        compare(sys.argv[2], sys.argv[3], sys.argv[4], sys.argv[5])
    elif cmd == "reached":
        reached(sys.argv[2], sys.argv[3])
    else:
        sys.exit(__doc__)
