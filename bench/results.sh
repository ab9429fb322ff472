#!/usr/bin/env bash
# Regenerates the tables of docs/results/<paper>/ with the bench commands that produce them.
# Each table file starts with the exact command that wrote it. Usage:
#   bench/results.sh [quick|full]
# quick (the default) uses fewer trials and repetitions than the papers (minutes on two cores);
# full uses the papers' counts (hours). Run from the repository root after
# `cargo build --release`.
set -euo pipefail
mode=${1:-quick}
strider=${STRIDER:-target/release/strider}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

case "$mode" in
  quick) reps=10; runs=5; trials=5; large=2 ;;
  full) reps=100; runs=25; trials=25; large=25 ;;
  *) echo "usage: bench/results.sh [quick|full]" >&2; exit 2 ;;
esac

# run NAME ARGS...: runs `strider ARGS... --out $out/NAME`.
run() {
  local name=$1
  shift
  echo "== strider $* ($name)" >&2
  "$strider" "$@" --out "$out/$name" >"$out/$name.log" 2>&1 || {
    tail -5 "$out/$name.log" >&2
    exit 1
  }
}

# keep KEY FILE...: copies generated tables into docs/results/KEY/.
keep() {
  local key=$1
  shift
  mkdir -p "docs/results/$key"
  for f in "$@"; do cp "$out/$f" "docs/results/$key/"; done
}

run tours tours
keep martin-corke tours/tours.md
run tours-worlds tours --world-seeds 10 --seeds 10
cp "$out/tours-worlds/worlds.md" docs/results/martin-corke/tours-worlds.md
run c4 learn c4-vegetation
keep pragr23 c4/c4_vegetation.md
run learn learn bench --reps "$reps"
keep pragr19 learn/learn_bench.md
keep pragr18 learn/c1_table.md
run navigate navigate --runs "$runs"
keep nardi19 navigate/navigate.md
run table5 bench table5 --trials "$trials" --large-trials "$large" --world-seeds 5
keep pragr22 table5/table5.md
echo "tables written to docs/results/*/" >&2
