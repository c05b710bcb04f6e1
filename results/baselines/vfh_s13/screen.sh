#!/bin/bash
# screen.sh OUTDIR WORLD... : VFH+ seed 0 on the family worlds, one at a time, this tree
out=$1; shift; mkdir -p $out
cd /work/wt/s13vfh
for w in "$@"; do
  PYTHONPATH=$PWD /work/venv/bin/python -m nav_bench episode results/baselines/bugs_s6/worlds/$w.yaml --planner vfh_plus --seed 0 --json --plot $out/$w.png --trace $out/$w.npz > $out/$w.json 2>/dev/null
  /work/venv/bin/python -c "
import json;r=json.load(open('$out/$w.json'));print('$w',r['outcome'],r['time_s'],round(r['path_length_m'],1),r['collisions'],round(r.get('cpu_s'),2))"
done
