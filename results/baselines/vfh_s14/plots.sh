#!/bin/bash
# plots.sh TREE OUT WORLD... : VFH+ seed 0 episodes with --plot and --trace, one at a time
tree=$1; out=$2; shift 2; mkdir -p $out; cd $tree
for w in "$@"; do
  PYTHONPATH=$tree /work/venv/bin/python -m nav_bench episode results/baselines/bugs_s6/worlds/$w.yaml --planner vfh_plus --seed 0 --json --plot $out/$w.png --trace $out/$w.npz > $out/$w.json 2>/dev/null
  /work/venv/bin/python -c "
import json;r=json.load(open('$out/$w.json'));print('$w',r['outcome'],r['time_s'],round(r['path_length_m'],1),r['collisions'],r.get('stuck_reason'))"
done
