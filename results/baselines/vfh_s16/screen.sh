#!/bin/bash
# screen.sh PLANNER OUT WORLD...: VFH+ episodes, one at a time, from this tree, for each seed in
# $SEEDS (default 0); prints world seed outcome time path contacts stuck_reason.
# PLANNER: a --planner value, e.g. vfh_plus:carve_memory_s=10,carve_undo_on_axis=true
spec=$1; out=$2; shift 2; mkdir -p $out; tree="$(cd "$(dirname "$0")/../../.." && pwd)"; cd $tree
for s in ${SEEDS:-0}; do for w in "$@"; do
  PYTHONPATH=$tree /work/venv/bin/python -m nav_bench episode results/baselines/bugs_s6/worlds/$w.yaml --planner "$spec" --seed $s --json ${PLOT:+--plot $out/${w}_s$s.png} --trace $out/${w}_s$s.npz > $out/${w}_s$s.json 2>$out/${w}_s$s.err
  /work/venv/bin/python -c "
import json;r=json.load(open('$out/${w}_s$s.json'));print('$w',$s,r['outcome'],r['time_s'],round(r['path_length_m'],1),r['collisions'],r.get('stuck_reason'))"
done; done
