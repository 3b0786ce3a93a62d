#!/usr/bin/env bash
# Computes the continuous phase's flow in scenes/contactor.toml's disc-and-doughnut column with
# OpenFOAM (Debian's package, v1912): steady laminar water flowing down at 8 mm/s mean, on a
# 5-degree axisymmetric wedge (tools/cfd/case). Then exports the velocity:
#   tools/cfd/output/contactor_wedge.vtk  foamToVTK's legacy binary file of the wedge (U, p)
#   tools/cfd/output/contactor_rz.vti     the axisymmetric (u_r, u_z) table on a regular (r, z)
#                                         grid (tools/cfd/wedge_to_axisymmetric.py)
# and prints the convergence and the flow rate through the inlet, the outlet and 9 cuts.
#
# On a fresh Debian machine, as root: bash tools/cfd/contactor.sh
# (installs openfoam and python3 with apt-get if simpleFoam or python3 is missing).
# Options: --no-install (never call apt-get), --3d (also write output/contactor_3d.vti).
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
case_dir="$here/case"
out_dir="$here/output"
install=1
three_d=0
for arg in "$@"; do
    case "$arg" in
        --no-install) install=0 ;;
        --3d) three_d=1 ;;
        *) echo "unknown option $arg" >&2; exit 2 ;;
    esac
done

# --- OpenFOAM ---------------------------------------------------------------------------------
if ! command -v simpleFoam >/dev/null 2>&1 || ! command -v python3 >/dev/null 2>&1; then
    if [ "$install" = 1 ]; then
        export DEBIAN_FRONTEND=noninteractive
        apt-get update
        apt-get install -y openfoam python3
    fi
fi
# Debian's package puts the applications in /usr/bin, on PATH already; they only need
# WM_PROJECT_DIR to find their etc/ files (etc/controlDict, the #includeFunc and #includeEtc
# dictionaries), which the package installs in /usr/share/openfoam/etc. Sourcing
# /usr/share/openfoam/etc/bashrc sets it too, but complains about helper scripts
# (bin/foamEtcFile) that the package does not ship. An upstream installation's bashrc is
# sourced instead when there is no simpleFoam on PATH.
if command -v simpleFoam >/dev/null 2>&1; then
    if [ -z "${WM_PROJECT_DIR:-}" ] && [ -f /usr/share/openfoam/etc/controlDict ]; then
        export WM_PROJECT_DIR=/usr/share/openfoam
    fi
else
    for rc in /usr/lib/openfoam/openfoam*/etc/bashrc /opt/openfoam*/etc/bashrc; do
        if [ -f "$rc" ]; then
            set +eu
            # shellcheck disable=SC1090
            . "$rc"
            set -eu
            break
        fi
    done
fi
command -v simpleFoam >/dev/null 2>&1 || { echo "no OpenFOAM (simpleFoam) found" >&2; exit 1; }

# --- the case ---------------------------------------------------------------------------------
cd "$case_dir"
# Clean the products of an earlier run (the inputs are 0/, constant/*Properties, system/).
rm -rf constant/polyMesh postProcessing VTK log.* [1-9]* 0.[0-9]*

run() {  # run APP [ARGS]: log to log.APP, stop on failure
    local app="$1"
    echo "== $*"
    if ! "$@" > "log.$app" 2>&1; then
        tail -30 "log.$app" >&2
        echo "$app failed (tools/cfd/case/log.$app)" >&2
        exit 1
    fi
}

start=$(date +%s)
run blockMesh
run checkMesh
grep -q "^Mesh OK" log.checkMesh || { echo "checkMesh found errors (log.checkMesh)" >&2; exit 1; }
run topoSet
run simpleFoam
latest=$(foamListTimes -latestTime 2>/dev/null | tail -1 || true)
[ -n "$latest" ] || latest=$(ls -d [1-9]* | sort -n | tail -1)
run foamToVTK -legacy -latestTime -no-boundary -fields '(U p)'
end=$(date +%s)

# --- results ------------------------------------------------------------------------------------
echo
echo "mesh: $(grep -m1 '^ *cells:' log.checkMesh | awk '{print $2}') cells"
echo "$(grep -E '^ *(hexahedra|prisms|polyhedra):' log.checkMesh | tr -s ' ' | tr '\n' ';')"
echo "SIMPLE iterations: $latest; OpenFOAM wall time $((end - start)) s"
res=postProcessing/residuals/0/solverInfo.dat
awk '!/^#/ {last=$0} END {split(last, f, "\t");
     printf "final initial residuals: Ux %s  Uy %s  Uz %s  p %s\n", f[3], f[6], f[9], f[14]}' "$res"
awk '/runTimeControl converged output:/ {buf = ""} {buf = buf $0 "\n"} END {printf "%s", buf}' \
    log.simpleFoam | grep -E "field|satisfied|Stopping" || true
# The wedge's faces are flat: its cross-section is R^2 sin(5 deg)/2, so the whole column's
# flow rate is the wedge's times 2 pi/sin(5 deg) = 72.0916; the target is
# 0.008 pi 0.025^2 = 1.570796e-5 m3/s (2.178893e-7 through the wedge).
echo "flow rate, last iteration (patches: + = out of the domain; cuts zNNN at z = 0.NNN m: + = up):"
for f in postProcessing/flowRate_*/0/surfaceFieldValue.dat; do
    name=$(basename "$(dirname "$(dirname "$f")")")
    awk -v n="${name#flowRate_}" '!/^#/ {v=$2} END {
        printf "  %-7s %+.6e m3/s (wedge)  %+.6e m3/s (column)  |Q| %+.4f %% off 1.570796e-5\n",
               n, v, v * 72.0916, ((v < 0 ? -v : v) * 72.0916 / 1.570796e-5 - 1) * 100 }' "$f"
done

mkdir -p "$out_dir"
vtk=$(ls VTK/*_"$latest".vtk 2>/dev/null || ls VTK/*.vtk | tail -1)
cp "$vtk" "$out_dir/contactor_wedge.vtk"
python3 "$here/wedge_to_axisymmetric.py" "$out_dir/contactor_wedge.vtk" "$out_dir/contactor_rz.vti"
if [ "$three_d" = 1 ]; then
    python3 "$here/wedge_to_axisymmetric.py" --3d "$out_dir/contactor_wedge.vtk" "$out_dir/contactor_3d.vti"
fi
echo
ls -l "$out_dir"
