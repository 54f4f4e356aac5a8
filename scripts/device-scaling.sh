#!/usr/bin/env bash
# Issue 27's 2–16 thread table, prepared for one run on a lent many-core
# machine (the session's `device` tool: a copy of the working tree, the
# ignored paths named in `carry`, results under $OUT).
#
#   scripts/device-scaling.sh stage    # here: release build, then everything the run needs
#                                      # in target/device/ (about 60 MB: the carry limit is 64 MiB)
#   scripts/device-scaling.sh run      # there: command "bash scripts/device-scaling.sh run",
#                                      # carry ["target/device"], timeout_s 560
#
# `run` measures, on the machine it runs on, with the staged binaries only
# (no build, no ../shared):
#   - `rpbrt-bench scaling`: hair-eumel-2-256 and hair-blonde-3-bounces-256
#     at 32 spp, seed 100, 2, 4, 8 and 16 threads, 2 interleaved rounds,
#     rpbrt beside pbrt-v4 (same spp and seed: equal error, see scaling.rs);
#   - `rpbrt-bench curves`: the refs README's 120 MB curve file at 2 and 16
#     threads, 1 round;
# and writes both tables, the machine's description and the log to $OUT
# (target/device/out without it). About 3 minutes on 16 cores; pbrt-v4 at
# 2 threads is most of it. Where the staged pbrt-v4 does not start (its
# binary uses AVX-512: it stops with SIGILL on processors without it), the
# tables are rpbrt's alone and scaling.md says so.
#
# Environment: RPBRT_BIN_DIR (stage) takes rpbrt and rpbrt-bench from
# another folder, e.g. target/pgo/use/release after scripts/pgo-build.sh;
# SHARED (stage) is the shared folder (default ../shared).
set -euo pipefail
cd "$(dirname "$0")/.."
device=target/device

stage() {
    local shared=${SHARED:-../shared}
    local bin=${RPBRT_BIN_DIR:-}
    if [ -z "$bin" ]; then
        cargo build --release --workspace
        bin=target/release
    fi
    rm -rf "$device"
    mkdir -p "$device/bin" "$device/pbrt-v4" "$device/scenes/derived" \
        "$device/scenes/pbrt-v4-scenes/hair/geometry" "$device/scenes/pbrt-v4-scenes/hair/textures"
    for program in rpbrt rpbrt-bench; do
        strip -o "$device/bin/$program" "$bin/$program"
    done
    cp "$shared"/tools/pbrt-v4/{pbrt.xz,lib.tar.xz,unpack.sh} "$device/pbrt-v4/"
    cp "$shared"/scenes/derived/{hair-eumel-2-256,hair-blonde-3-bounces-256}.pbrt "$device/scenes/derived/"
    cp "$shared"/scenes/pbrt-v4-scenes/hair/geometry/{curly-hair,straight-hair}.pbrt.gz \
        "$device/scenes/pbrt-v4-scenes/hair/geometry/"
    cp "$shared"/scenes/pbrt-v4-scenes/hair/textures/sunflowers_equiarea_blurred.exr \
        "$device/scenes/pbrt-v4-scenes/hair/textures/"
    local bytes
    bytes=$(du -sb "$device" | cut -f1)
    echo "staged $((bytes >> 20)) MiB in $device (the carry limit is 64 MiB)"
    if [ "$bytes" -gt $((64 << 20)) ]; then
        echo "too large to carry" >&2
        exit 1
    fi
    echo 'now: run(command="bash scripts/device-scaling.sh run", carry=["target/device"], timeout_s=560)'
}

run() {
    local out=${OUT:-$device/out}
    mkdir -p "$out"
    local log=$out/log.txt
    {
        echo "machine: $(nproc) cores; $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"
        grep -m1 -o -w 'avx512bw' /proc/cpuinfo || echo "no AVX-512"
        free -g | head -2
    } > "$out/machine.txt" 2>&1
    local pbrt_args=()
    if pbrt=$("$device/pbrt-v4/unpack.sh" /tmp/pbrt-v4 2>>"$log"); then
        pbrt_args=(--pbrt "$pbrt")
    else
        echo "pbrt-v4 does not start here: rpbrt alone" >> "$out/machine.txt"
    fi
    local scenes=$device/scenes/derived
    "$device/bin/rpbrt-bench" scaling \
        --scenes "$scenes/hair-eumel-2-256.pbrt,$scenes/hair-blonde-3-bounces-256.pbrt" \
        --threads 2,4,8,16 --spp 32 --seed 100 --rounds 2 "${pbrt_args[@]}" \
        > "$out/scaling.md" 2>>"$log"
    "$device/bin/rpbrt-bench" curves --threads 2,16 --rounds 1 "${pbrt_args[@]}" \
        > "$out/curves.md" 2>>"$log"
    cat "$out/machine.txt" "$out/scaling.md" "$out/curves.md"
}

case "${1:-}" in
    stage) stage ;;
    run) run ;;
    *)
        echo "usage: scripts/device-scaling.sh stage|run" >&2
        exit 2
        ;;
esac
