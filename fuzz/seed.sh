#!/usr/bin/env bash
# Seeds fuzz/corpus/parse with the small scene files of ../shared/scenes
# (not committed: they come from public repositories under their own licences).
set -eu
cd "$(dirname "$0")"
mkdir -p corpus/parse
find ../../shared/scenes -name '*.pbrt' -size -64k -exec cp {} corpus/parse/ \;
ls corpus/parse | wc -l
