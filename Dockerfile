# wetbounce in a container: the command-line program (with rerun's recording) and the Python
# module, built from this folder in one command (docs/install.md):
#
#     docker build -t wetbounce .
#     docker run --rm -v "$PWD/out:/wetbounce/out" wetbounce wetbounce run scenes/toluene_drop.toml
#     docker run --rm wetbounce python3 -c "import wetbounce; print(wetbounce.__version__)"
#
# The build stage runs tools/dist.sh, the same command that makes the archive and the wheel a
# user without Rust installs; the image keeps only what those two give, on Debian 12: the
# stripped program on PATH, the module with its dependencies in /opt/venv (first on PATH), and
# the archive's scenes, docs, licences and citation in /wetbounce, the working folder.
FROM rust:1.95-slim-bookworm AS build
RUN apt-get update \
    && apt-get install -y --no-install-recommends python3 python3-venv \
    && rm -rf /var/lib/apt/lists/*
RUN python3 -m venv /opt/maturin && /opt/maturin/bin/pip install --no-cache-dir maturin==1.16.0
WORKDIR /src
COPY . .
RUN PATH="/opt/maturin/bin:$PATH" bash tools/dist.sh /dist \
    && mkdir /dist/cli && tar -xzf /dist/wetbounce-*.tar.gz -C /dist/cli --strip-components=1

FROM debian:bookworm-slim
RUN apt-get update \
    && apt-get install -y --no-install-recommends python3 python3-venv \
    && rm -rf /var/lib/apt/lists/*
COPY --from=build /dist/*.whl /tmp/
RUN python3 -m venv /opt/venv \
    && /opt/venv/bin/pip install --no-cache-dir /tmp/wetbounce-*.whl \
    && rm /tmp/wetbounce-*.whl
COPY --from=build /dist/cli /wetbounce
RUN mv /wetbounce/wetbounce /usr/local/bin/wetbounce
ENV PATH="/opt/venv/bin:$PATH"
WORKDIR /wetbounce
CMD ["wetbounce", "--help"]
