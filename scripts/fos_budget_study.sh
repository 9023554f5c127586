#!/usr/bin/env bash
# How the factor of safety depends on the failure criterion's parameters: the search of CASE at
# cell size H in MODE (trials | incremental) as given, then with each budget doubled (Newton's
# iterations, the halvings to the smallest load or reduction step) and min_stiffness halved, one
# change at a time. Prints a Markdown table: a factor that moves by more than the search
# tolerance when a budget is doubled depends on the budget, not on the slope.
#   [THREADS=n] scripts/fos_budget_study.sh CASE H MODE [OUT_DIR]   (talus from build/, or $TALUS)
set -euo pipefail
[ $# -ge 3 ] || { echo "usage: $0 CASE H MODE [OUT_DIR]" >&2; exit 2; }
case_file="$1"; h="$2"; mode="$3"; out="${4:-results/fos-budget-study}"
mkdir -p "$out"
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
talus="${TALUS:-$repo/build/talus}"

# The case's own budgets, read back from the case file (talus check prints nothing of them).
value() { sed -n "s/.*\b$1: *\([0-9.eE+-]*\).*/\1/p" "$case_file" | head -1; }
iterations=$(value max_newton_iterations); min_dt=$(value min_dt); min_stiffness=$(value min_stiffness)
iterations=${iterations:-12}; min_stiffness=${min_stiffness:-0.1}
[ -n "$min_dt" ] || { echo "$0: $case_file sets no time.min_dt" >&2; exit 2; }

half() { awk -v d="$1" 'BEGIN { printf "%.10g", d / 2 }'; }
# The smallest step: the loading's time.min_dt, and in the incremental mode also the reduction
# steps' min_step (a 64th of the tolerance unless the case sets it).
smallest="time.min_dt=$(half "$min_dt")"
if [ "$mode" = incremental ]; then
  tolerance=$(value tolerance); min_step=$(value min_step)
  min_step=${min_step:-$(awk -v t="${tolerance:-0.01}" 'BEGIN { printf "%.10g", t / 64 }')}
  smallest="$smallest strength_reduction.min_step=$(half "$min_step")"
fi
variants=(
  "as given|"
  "max_newton_iterations x2|solver.max_newton_iterations=$((2 * iterations))"
  "smallest step / 2|$smallest"
  "min_stiffness / 2|strength_reduction.min_stiffness=$(awk -v s="$min_stiffness" 'BEGIN { printf "%g", s / 2 }')"
)
echo "| $(basename "$case_file") h = $h, $mode | factor | bracket | Newton iterations | CPU [s] |"
echo "|---|---|---|---|---|"
for v in "${variants[@]}"; do
  label="${v%%|*}"; override="${v#*|}"
  dir="$out/$(echo "$label" | tr -c 'a-z0-9\n' '_')"
  args=(--threads "${THREADS:-0}" --set "grid.cell_size=$h" --set "strength_reduction.mode=$mode")
  for o in $override; do args+=(--set "$o"); done
  "$talus" fos "$case_file" --out "$dir" --force "${args[@]}" > "$dir.log" 2>&1 || true
  line=$(grep "factor of safety" "$dir.log" | tail -1)
  [ -n "$line" ] || { echo "$0: no factor in $dir.log" >&2; exit 1; }
  factor=$(echo "$line" | sed -n 's/.*factor of safety \([0-9.]*\).*/\1/p')
  bracket=$(echo "$line" | sed -n 's/.*bracket \(\[[^]]*\]\).*/\1/p')
  newton=$(echo "$line" | sed -n 's/.* \([0-9]*\) Newton iterations.*/\1/p')
  cpu=$(echo "$line" | sed -n 's/.*(\([0-9.]*\) s of CPU).*/\1/p')
  echo "| $label | $factor | $bracket | $newton | $cpu |"
done
