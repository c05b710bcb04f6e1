#!/bin/bash
# main = this tree; G3 = a copy in /tmp/s17vfhd/g3 of this tree with ../candidate_G3_brake.patch applied
# one at a time: main (worktree) then G3 (copy) for each episode
for ep in "clutter_0 1" "clutter_0 2" "office_11 1"; do set -- $ep; w=$1; s=$2
 for side in main g3; do
  if [ $side = main ]; then tree=/work/wt/s17vfhd; else tree=/tmp/s17vfhd/g3; fi
  cd $tree
  /usr/bin/time -f "%U cpu" env PYTHONPATH=$tree /work/venv/bin/python -m nav_bench episode results/baselines/bugs_s6/worlds/$w.yaml --planner vfh_plus --seed $s --json --plot /tmp/s17vfhd/${w}_s${s}_$side.png --trace /tmp/s17vfhd/${w}_s${s}_$side.npz > /tmp/s17vfhd/${w}_s${s}_$side.json 2>/tmp/s17vfhd/${w}_s${s}_$side.err
  echo $w $s $side $(python3 -c "import json;r=json.load(open('/tmp/s17vfhd/${w}_s${s}_$side.json'));print(r['outcome'],r['time_s'],r['collisions'],r.get('stuck_reason'))") $(tail -1 /tmp/s17vfhd/${w}_s${s}_$side.err)
 done
done
