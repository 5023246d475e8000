#!/usr/bin/env bash
# One render in one process against the same render spread over MPI ranks, side by side:
# rounds alternate the two, so a busy shared machine slows both alike. Prints each round,
# then the medians and the speed ratio (distributed / one process), for the render alone
# (lancer's "render X s": from the first sample to the image) and for the whole command
# (starting the processes, loading the scene and building the tree on every rank included).
# Every round also checks that both wrote the same EXR bytes.
#
#   bench/mpi/mpi_speed.sh [--ranks N] [--rank-threads T] [--threads T] [--rounds K]
#                          [--scene FILE] [--width W] [--spp S] [--lancer BIN]
# Defaults: 2 ranks x 1 thread against 1 process x 2 threads, 5 rounds, the Cornell box,
# 256x256, 96 spp (about 5 s a render on two cores).
set -euo pipefail
here=$(cd "$(dirname "$0")/../.." && pwd)
ranks=2 rank_threads=1 threads=2 rounds=5 width=256 spp=96
scene=$here/scenes/cornell-box.gltf lancer=$here/build/release/lancer
while [ $# -gt 0 ]; do
  case $1 in
    --ranks) ranks=$2 ;; --rank-threads) rank_threads=$2 ;; --threads) threads=$2 ;;
    --rounds) rounds=$2 ;; --scene) scene=$2 ;; --width) width=$2 ;; --spp) spp=$2 ;;
    --lancer) lancer=$2 ;;
    *) echo "mpi_speed: unknown option $1" >&2; exit 2 ;;
  esac
  shift 2
done
command -v mpirun >/dev/null || { echo "mpi_speed: mpirun not found (install openmpi-bin)" >&2; exit 1; }
[ -x "$lancer" ] || { echo "mpi_speed: $lancer not built (make build)" >&2; exit 1; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
mpi=(mpirun --oversubscribe -np "$ranks")
[ "$(id -u)" -eq 0 ] && mpi+=(--allow-run-as-root)
common=(render "$scene" --width "$width" --spp "$spp" --no-progress)

# Runs a command, prints "<render seconds> <wall seconds>".
timed() {
  local start end log
  start=$(date +%s.%N)
  log=$("$@" 2>&1) || { echo "mpi_speed: failed: $*" >&2; echo "$log" >&2; exit 1; }
  end=$(date +%s.%N)
  echo "$(grep -o 'render [0-9.]* s' <<<"$log" | head -1 | awk '{print $2}') $(awk -v a="$start" -v b="$end" 'BEGIN {printf "%.2f", b - a}')"
}
median() { sort -g | awk '{a[NR] = $1} END {print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2}'; }

echo "scene $(basename "$scene") ${width}px ${spp} spp; one process x $threads threads against $ranks ranks x $rank_threads threads; $rounds rounds"
echo "round  one: render s  wall s   mpi: render s  wall s"
: >"$out/one" && : >"$out/mpi"
for r in $(seq 1 "$rounds"); do
  one=$(timed "$lancer" "${common[@]}" --threads "$threads" -o "$out/one.exr")
  dist=$(timed "${mpi[@]}" "$lancer" "${common[@]}" --threads "$rank_threads" -o "$out/mpi.exr")
  cmp -s "$out/one.exr" "$out/mpi.exr" || { echo "mpi_speed: the images differ" >&2; exit 1; }
  echo "$one" >>"$out/one" && echo "$dist" >>"$out/mpi"
  printf "%5d  %13s %7s  %14s %7s\n" "$r" $one $dist
done
one_render=$(cut -d' ' -f1 "$out/one" | median) one_wall=$(cut -d' ' -f2 "$out/one" | median)
mpi_render=$(cut -d' ' -f1 "$out/mpi" | median) mpi_wall=$(cut -d' ' -f2 "$out/mpi" | median)
echo "median  $one_render $one_wall    $mpi_render $mpi_wall"
ratio() { awk -v a="$1" -v b="$2" 'BEGIN {printf "%.3f", a / b}'; }
echo "speed, distributed / one process: render $(ratio "$one_render" "$mpi_render")x, whole command $(ratio "$one_wall" "$mpi_wall")x (images identical in every round)"
