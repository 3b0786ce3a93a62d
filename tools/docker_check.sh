#!/usr/bin/env bash
# Builds the repository's Dockerfile and checks the image as a user would use it: the shipped
# scene runs and writes its files into a mounted folder, the module imports and runs a scene,
# and python/tests pass against the image's program and module.
#
#     bash tools/docker_check.sh [--standins]
#
# It needs a running Docker daemon, and the two base images of the Dockerfile
# (rust:1.95-slim-bookworm, debian:bookworm-slim) from Docker Hub. Where Docker Hub cannot be
# reached (this project's machines reach only the package registries), --standins makes local
# images under those two names first: Debian 12 by debootstrap from Debian's mirror, and the
# same with gcc and this machine's Rust toolchain (`rustc --print sysroot`) on PATH, which is
# what the official rust image holds. Both also trust this machine's own certificate
# authorities (/usr/local/share/ca-certificates, and the bundle in PIP_CERT's place), which a
# network behind a TLS-inspecting proxy needs for PyPI and crates.io. The Dockerfile itself is
# unchanged either way.
#
# Time on the 2-core machine: about 30 minutes (the build stage compiles the program with the
# rerun feature and the module, in release); disk: the images, about 3 GB with the stand-ins.
set -euo pipefail
cd "$(dirname "$0")/.."
tag=wetbounce-check

if [ "${1:-}" = "--standins" ]; then
  work=$(mktemp -d "${TMPDIR:-/tmp}/wetbounce-standins-XXXXXX")
  trap 'rm -rf "$work"' EXIT
  if ! docker image inspect debian:bookworm-slim >/dev/null 2>&1; then
    command -v debootstrap >/dev/null || apt-get install -y debootstrap
    debootstrap --variant=minbase bookworm "$work/root" http://deb.debian.org/debian >/dev/null
    mkdir -p "$work/root/usr/local/share/ca-certificates" "$work/root/etc/ssl/certs"
    cp /usr/local/share/ca-certificates/*.crt "$work/root/usr/local/share/ca-certificates/" 2>/dev/null || true
    cp /etc/ssl/certs/ca-certificates.crt "$work/root/etc/ssl/certs/ca-certificates.crt"
    tar -C "$work/root" -c . | docker import \
      --change 'ENV PIP_CERT=/etc/ssl/certs/ca-certificates.crt SSL_CERT_FILE=/etc/ssl/certs/ca-certificates.crt' \
      --change 'ENV PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin' \
      - debian:bookworm-slim
  fi
  if ! docker image inspect rust:1.95-slim-bookworm >/dev/null 2>&1; then
    mkdir "$work/rust"
    cp -a "$(rustc --print sysroot)" "$work/rust/toolchain"
    cat >"$work/rust/Dockerfile" <<'STANDIN'
FROM debian:bookworm-slim
RUN apt-get update \
    && apt-get install -y --no-install-recommends ca-certificates gcc libc6-dev \
    && rm -rf /var/lib/apt/lists/*
COPY toolchain /usr/local/rust
ENV CARGO_HOME=/usr/local/cargo PATH=/usr/local/cargo/bin:/usr/local/rust/bin:$PATH
STANDIN
    docker build -q -t rust:1.95-slim-bookworm "$work/rust"
  fi
fi

start=$SECONDS
docker build -t "$tag" .
echo "docker build: $((SECONDS - start)) s; image $(docker image inspect -f '{{.Size}}' "$tag" | awk '{printf "%.0f MB", $1 / 1e6}')"

out=$(mktemp -d "${TMPDIR:-/tmp}/wetbounce-docker-out-XXXXXX")
# The shipped scene, its files in a folder of the host.
docker run --rm -v "$out:/wetbounce/out" "$tag" wetbounce run scenes/toluene_drop.toml --quiet
for f in toluene_drop.mcap toluene_drop.rrd summary.json; do
  [ -s "$out/toluene_drop/$f" ] || { echo "docker run: no out/toluene_drop/$f" >&2; exit 1; }
done
# The module, from the image's Python.
docker run --rm "$tag" python3 -c '
import wetbounce
sim = wetbounce.Scene.load("scenes/toluene_drop.toml").run()
print("module", wetbounce.__version__, "ran to t =", sim.time)'
# python/tests against the image's program and module (pytest and the tests' packages are
# installed into a throw-away container, not into the image).
docker run --rm -v "$PWD:/repo:ro" -w /repo -e WETBOUNCE_BIN=/usr/local/bin/wetbounce "$tag" sh -c '
  pip install --quiet --no-cache-dir -r python/requirements-ci.txt >/dev/null &&
  python3 -m pytest -q -p no:cacheprovider python/tests'
rm -rf "$out"
echo "tools/docker_check.sh: the image works"
