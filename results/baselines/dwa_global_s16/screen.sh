# The screen of dwa_global_s16: main's 7 dwa_global family failures replayed with a parameter set.
#   bash screen.sh TREE OUT PLANNERSPEC [episode args]   e.g.  bash screen.sh . /tmp/s both "dwa_global:goal_tolerance=0.1"
# TREE: the checkout to play; OUT/NAME.json per world and one summary line each on stdout.
TREE=$(cd "$1" && pwd); OUT=$2; P=$3; shift 3; mkdir -p "$OUT"
for w in maze_7 maze_8 maze_18 clutter_1 clutter_6 clutter_11 clutter_17; do
  PYTHONPATH=$TREE python -m nav_bench episode "$TREE/results/baselines/bugs_s6/worlds/$w.yaml" --planner "$P" \
    --seed 0 --json "$@" > "$OUT/$w.json" 2>/dev/null
  python -c "import json; r=json.load(open('$OUT/$w.json')); print('$w', r['outcome'], r.get('stuck_reason'), round(r['time_s'], 1), round(r['path_length_m'], 1), round(r['goal_distance_m'], 2), r['collisions'])"
done
