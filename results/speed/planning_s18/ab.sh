#!/usr/bin/env bash
# planning cost per cycle, 50b2d2e (session start) vs HEAD, one round each, alternated
OUT=${OUT:-/tmp/planning_s18}; mkdir -p $OUT
for r in 1 2 3 4; do
  for t in s18base main; do
    d=${BASE:?a worktree of 50b2d2e}; [ $t = main ] && d=$PWD
    (cd $d && PYTHONPATH=$d ${PYTHON:-python} benchmarks/bench_planning.py --big-only --time-s 40 --rounds 1 --planners vfh_plus,bug2,tangent_bug,dstar_lite > $OUT/${t}_r$r.txt 2>&1)
  done
done
echo done > $OUT/DONE
