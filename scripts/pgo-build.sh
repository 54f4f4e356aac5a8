#!/usr/bin/env bash
# The release build with profile-guided optimisation (PGO): rpbrt and
# rpbrt-bench built once with instrumentation, run on a training set made
# here (no ../shared needed), then built again with the branch and call
# counts of those runs. Same code and arithmetic as `cargo build --release`
# (the images are byte-identical); the shared hair scenes render with
# 6–9 % less CPU time on the developers' machines (docs/performance-notes.md, "Session 26").
#
# Usage: scripts/pgo-build.sh   → target/pgo/use/release/{rpbrt,rpbrt-bench}
#
# Needs llvm-profdata from an LLVM that reads rustc's raw profiles:
# $LLVM_PROFDATA if set, else rustup's llvm-tools component, else the
# newest /usr/lib/llvm-*/bin/llvm-profdata (Debian: `apt-get install
# llvm-19`; LLVM 19 reads the profiles of rustc 1.95's LLVM 22).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
pgo=$root/target/pgo
train=$pgo/train
profiles=$pgo/profiles

find_profdata() {
    if [ -n "${LLVM_PROFDATA:-}" ]; then
        echo "$LLVM_PROFDATA"
        return
    fi
    local sysroot candidate
    sysroot=$(rustc --print sysroot)
    for candidate in "$sysroot"/lib/rustlib/*/bin/llvm-profdata \
        $(ls -d /usr/lib/llvm-*/bin/llvm-profdata 2>/dev/null | sort -t- -k2 -n -r); do
        if [ -x "$candidate" ]; then
            echo "$candidate"
            return
        fi
    done
    echo "pgo-build: no llvm-profdata found: set LLVM_PROFDATA, or install rustup's" \
        "llvm-tools component or Debian's llvm-19" >&2
    exit 1
}
profdata=$(find_profdata)
echo "pgo-build: merging profiles with $profdata"

echo "pgo-build: 1/4 instrumented build"
RUSTFLAGS="-Cprofile-generate=$profiles" \
    cargo build --release -p rpbrt -p rpbrt-bench --bins --target-dir "$pgo/generate"
# Build scripts ran instrumented too: keep only the training's counts.
rm -rf "$profiles" "$train"
mkdir -p "$profiles" "$train"
rpbrt=$pgo/generate/release/rpbrt

echo "pgo-build: 2/4 training renders"
# An environment map with some structure: the shipped spheres scene seen
# through an equal-area spherical camera (the square image infinite
# lights read).
sed -e 's/^Camera .*/Camera "spherical" "string mapping" "equalarea"/' \
    -e 's/"integer xresolution" \[ *[0-9]* *\]/"integer xresolution" [ 128 ]/' \
    -e 's/"integer yresolution" \[ *[0-9]* *\]/"integer yresolution" [ 128 ]/' \
    pbrt-scenes/spheres.pbrt >"$train/sky.pbrt"
(cd pbrt-scenes && "$rpbrt" --quiet --spp 16 --outfile "$train/sky.exr" "$train/sky.pbrt")

# A ball of hair: random cubic curves wound round a sphere, lit by that
# map, rendered as the shared hair scenes are (volpath, halton, dark
# and light hair, long and short paths); a few megabytes of curves for
# the parser and build.
awk 'BEGIN {
    srand(26);
    for (i = 0; i < 24000; i++) {
        th = 6.2831853 * rand(); z = 2 * rand() - 1; r = sqrt(1 - z * z);
        x = r * cos(th); y = r * sin(th);
        dx = rand() - 0.5; dy = rand() - 0.5; dz = rand() - 0.5;
        printf "Shape \"curve\" \"string type\" [ \"cylinder\" ] \"point3 P\" [";
        for (k = 0; k < 4; k++) {
            s = 1 + 0.08 * k;
            printf " %.5f %.5f %.5f", s * x + k * 0.15 * dx, s * y + k * 0.15 * dy, s * z + k * 0.15 * dz;
        }
        printf " ] \"float width\" [ %.5f ]\n", 0.004 + 0.002 * rand();
    }
}' >"$train/hair-ball-curves.pbrt"
for setting in "2 32" "0.2 3" "0.2 32"; do
    read -r melanin depth <<<"$setting"
    cat >"$train/hair-ball.pbrt" <<EOF
LookAt 0 0 5  0 0 0  0 1 0
Camera "perspective" "float fov" [ 35 ]
Sampler "halton" "integer pixelsamples" [ 64 ]
Integrator "volpath" "integer maxdepth" [ $depth ]
Film "rgb" "integer xresolution" [ 96 ] "integer yresolution" [ 96 ]
    "string filename" [ "hair-ball.exr" ] "float maxcomponentvalue" 50
WorldBegin
LightSource "infinite" "string filename" "sky.exr"
Material "hair" "float beta_m" 0.25 "float eumelanin" $melanin
Include "hair-ball-curves.pbrt"
AttributeBegin
Material "diffuse" "rgb reflectance" [ .1 .1 .1 ]
Shape "sphere" "float radius" 0.9
AttributeEnd
EOF
    (cd "$train" && "$rpbrt" --quiet --spp 16 --outfile "$train/out.exr" hair-ball.pbrt)
done
# The shipped scenes (other samplers, lights, the dual model).
for scene in hair-strands hair-dual hair-dual-circular spheres; do
    (cd pbrt-scenes && "$rpbrt" --quiet --spp 4 --outfile "$train/out.exr" "$scene.pbrt")
done

echo "pgo-build: 3/4 merging"
if ! "$profdata" merge -o "$pgo/merged.profdata" "$profiles"; then
    echo "pgo-build: $profdata could not read rustc's profiles (rustc's LLVM is" \
        "$(rustc -vV | sed -n 's/^LLVM version: //p')): set LLVM_PROFDATA to a newer llvm-profdata" >&2
    exit 1
fi

echo "pgo-build: 4/4 optimised build"
RPBRT_PGO=1 RUSTFLAGS="-Cprofile-use=$pgo/merged.profdata" \
    cargo build --release -p rpbrt -p rpbrt-bench --bins --target-dir "$pgo/use"
echo "pgo-build: done: $pgo/use/release/rpbrt"
