#!/usr/bin/env bash
# Regenerates the results table of README.md: runs `uascma reproduce --quick --seed 1` and puts the table.md it
# writes, unedited, between the README's marker comments ("generated: uascma reproduce --quick --seed 1").
#   bash scripts/readme-results.sh [BUILD_DIR]      (~3 CPU minutes)
set -euo pipefail
build="$(cd "${1:-build}" && pwd)"
root="$(cd "$(dirname "$0")/.." && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cd "$root"
"$build/uascma" reproduce --quick --seed 1 --jobs 2 --out "$work/reproduce" > /dev/null
python3 - README.md "$work/reproduce/table.md" <<'PY'
import sys
readme_path, table_path = sys.argv[1:]
begin = "<!-- generated: uascma reproduce --quick --seed 1 (bash scripts/readme-results.sh), do not edit -->"
end = "<!-- end of generated: uascma reproduce -->"
readme = open(readme_path, encoding="utf-8").read()
if readme.count(begin) != 1 or readme.count(end) != 1:
    sys.exit(f"readme-results: {readme_path}: expected one '{begin}' and one '{end}'")
table = open(table_path, encoding="utf-8").read().strip()
head, rest = readme.split(begin)
_, tail = rest.split(end)
open(readme_path, "w", encoding="utf-8").write(f"{head}{begin}\n{table}\n{end}{tail}")
PY
echo "readme-results: README.md's table regenerated from $build/uascma"
