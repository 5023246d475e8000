#!/usr/bin/env bash
# What motion blur costs: the same render with the shutter open (--shutter OPEN,CLOSE) and
# as a still at its opening (--frame-time OPEN), side by side: rounds alternate the two, so
# a busy shared machine slows both alike. Prints each round's render seconds (lancer's
# "render X s"), the medians and the ratio blurred / still.
#
#   bench/motion/motion_cost.sh [--scene FILE] [--shutter OPEN,CLOSE] [--rounds K]
#                               [--width W] [--spp S] [--threads T] [--lancer BIN]
# Defaults: scenes/cornell-box-motion.gltf (a ball thrown over the short block, which turns
# 60 degrees), shutter 0,1, 5 rounds, 256x256, 64 spp, every core.
set -euo pipefail
here=$(cd "$(dirname "$0")/../.." && pwd)
scene=$here/scenes/cornell-box-motion.gltf shutter=0,1 rounds=5 width=256 spp=64 threads=0
lancer=$here/build/release/lancer
while [ $# -gt 0 ]; do
  case $1 in
    --scene) scene=$2 ;; --shutter) shutter=$2 ;; --rounds) rounds=$2 ;; --width) width=$2 ;;
    --spp) spp=$2 ;; --threads) threads=$2 ;; --lancer) lancer=$2 ;;
    *) echo "motion_cost: unknown option $1" >&2; exit 2 ;;
  esac
  shift 2
done
[ -x "$lancer" ] || { echo "motion_cost: $lancer not built (make build)" >&2; exit 1; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
common=(render "$scene" --width "$width" --spp "$spp" --threads "$threads" --no-progress -o "$out/image.exr")

render_seconds() {
  local log
  log=$("$lancer" "${common[@]}" "$@" 2>&1) || { echo "motion_cost: failed: $*" >&2; echo "$log" >&2; exit 1; }
  grep -o 'render [0-9.]* s' <<<"$log" | head -1 | awk '{print $2}'
}
median() { sort -g | awk '{a[NR] = $1} END {print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2}'; }

echo "scene $(basename "$scene") ${width}px ${spp} spp, shutter $shutter, $rounds rounds"
echo "round  still s  blurred s"
: >"$out/still" && : >"$out/blurred"
for r in $(seq 1 "$rounds"); do
  still=$(render_seconds --frame-time "${shutter%%,*}")
  blurred=$(render_seconds --shutter "$shutter")
  echo "$still" >>"$out/still" && echo "$blurred" >>"$out/blurred"
  printf "%5d  %7s  %9s\n" "$r" "$still" "$blurred"
done
s=$(median <"$out/still") b=$(median <"$out/blurred")
echo "median  $s  $b"
echo "cost of motion blur, blurred / still: $(awk -v a="$b" -v b="$s" 'BEGIN {printf "%.3f", a / b}')x"
