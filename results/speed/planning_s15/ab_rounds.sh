#!/usr/bin/env bash
# Per-cycle planning cost, an older revision and this tree alternated: six rounds, each plays
# D* Lite, dwa_global, VFH+ and EO/PC for 40 s in clutter_40m with one tree, then the other.
#   bash results/speed/planning_s15/ab_rounds.sh REV        (from the checkout's root)
# bench_planning.py is this tree's, with ROOT pointed at each tree (so each plays its own code).
set -eu
rev=${1:?usage: ab_rounds.sh REV}
old=$(mktemp -d)/before
git worktree add -q --detach "$old" "$rev"
trap 'git worktree remove --force "$old"' EXIT
script=$(mktemp --suffix=.py)
sed 's#^ROOT = .*#ROOT = Path(os.environ["BP_ROOT"])#' benchmarks/bench_planning.py > "$script"
for _ in 1 2 3 4 5 6; do
  for side in before after; do
    if [ "$side" = before ]; then tree=$old; else tree=$PWD; fi
    echo -n "$side "
    BP_ROOT=$tree PYTHONPATH=$tree python "$script" --big-only --time-s 40 \
      --planners dstar_lite,dwa_global,vfh_plus,eopc | grep "CPU: median" | awk '{printf "%s %s ", $1, $4}'
    echo
  done
done
