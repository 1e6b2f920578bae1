#!/usr/bin/env bash
# Fingerprints of the behaviour a refactor must preserve: run against two builds and diff the outputs.
#   bash scripts/same-behaviour.sh BUILD_DIR OUT_FILE [--quick]
# - the 930-flight default campaign (examples/campaign.yaml, seed 1): md5 of every runs column but wall_time_s,
#   rows ordered by flight_id;
# - the battery model learned from 5,000 flights (seed 1): its model hash (skipped with --quick);
# - Scenario I and II: the --json summary without wall_time_s and realtime_factor.
# SAME_BEHAVIOUR_IGNORE="name1,name2" leaves those runs columns and summary keys out as well: a change that only
# adds a column or a key compares with the new names ignored (and says so in its commit).
set -euo pipefail
build="$(cd "$1" && pwd)"
out="$2"
quick="${3:-}"
here="$(cd "$(dirname "$0")/.." && pwd)"
cli="$build/uascma"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cd "$here"
{
  "$cli" campaign examples/campaign.yaml --db "$work/c.db" --seed 1 --jobs 2 > /dev/null
  ignore="${SAME_BEHAVIOUR_IGNORE:-}"
  ignored="'wall_time_s'"
  for name in ${ignore//,/ }; do ignored+=",'$name'"; done
  columns=$(sqlite3 "$work/c.db" "select group_concat(name, ',') from pragma_table_info('runs') where name not in ($ignored)")
  echo "campaign seed 1 runs: $(sqlite3 "$work/c.db" "select count(*) from runs") rows, md5 $(sqlite3 "$work/c.db" \
    "select $columns from runs order by flight_id" | md5sum | cut -d' ' -f1)"
  if [[ "$quick" != "--quick" ]]; then
    "$cli" battery learn --runs 5000 --seed 1 --jobs 2 --out "$work/model.json" > /dev/null
    echo "battery model 5000 flights seed 1: hash $(python3 -c "import json, sys; print(json.load(open(sys.argv[1]))['hash'])" "$work/model.json")"
  fi
  for s in scenario-1 scenario-2; do
    echo "$s: $("$cli" simulate "examples/$s.yaml" --json | python3 -c "
import json, os, sys
d = json.load(sys.stdin)
skip = {'wall_time_s', 'realtime_factor'} | set(filter(None, os.environ.get('SAME_BEHAVIOUR_IGNORE', '').split(',')))
def strip(x):
    if isinstance(x, dict):
        return {k: strip(v) for k, v in x.items() if k not in skip}
    if isinstance(x, list):
        return [strip(v) for v in x]
    return x
print(json.dumps(strip(d), sort_keys=True))" | md5sum | cut -d' ' -f1)"
  done
} > "$out"
cat "$out"
