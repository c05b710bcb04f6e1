#!/bin/bash
# screen_mem.sh MEM OUT WORLD...: VFH+ seed 0 with carving.CARVE_MEMORY_S = MEM (monkeypatched), one at a time
mem=$1; out=$2; shift 2; mkdir -p $out; cd "$(dirname "$0")/../../.."
for w in "$@"; do
  PYTHONPATH=$PWD /work/venv/bin/python -c "
import sys, nav_bench.planners.carving as c
c.CARVE_MEMORY_S = $mem
from nav_bench.cli import main
sys.exit(main(['episode','results/baselines/bugs_s6/worlds/$w.yaml','--planner','vfh_plus','--seed','0','--json','--trace','$out/$w.npz']))" > $out/$w.json 2>/dev/null
  /work/venv/bin/python -c "
import json;r=json.load(open('$out/$w.json'));print('$w',r['outcome'],r['time_s'],round(r['path_length_m'],1),r['collisions'],r.get('stuck_reason'))"
done
