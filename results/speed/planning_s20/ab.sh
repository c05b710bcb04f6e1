#!/usr/bin/env bash
# planning cost per cycle, c9df58d (session start) vs HEAD, one round each, alternated, VFH+ only
OUT=${OUT:-/tmp/planning_s20}; mkdir -p $OUT
for r in 1 2 3 4; do
  for t in base main; do
    d=${BASE:?a worktree of c9df58d}; [ $t = main ] && d=$PWD
    (cd $d && PYTHONPATH=$d ${PYTHON:-python} benchmarks/bench_planning.py --big-only --time-s 40 --rounds 1 --planners vfh_plus > $OUT/${t}_r$r.txt 2>&1)
  done
done
echo done > $OUT/DONE
