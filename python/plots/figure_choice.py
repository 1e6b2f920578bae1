"""The entry point of the plotting scripts that draw one of several figures from one JSON file: the file's "figure"
key names which (battery_identification.py, propulsion_identification.py). Imported from beside them: a script's
folder is the first entry of sys.path."""
import json
import sys


def run(usage, drawers):
    """`script DATA.json OUT.png`: draws drawers[data["figure"]](data) and saves it; else exits with `usage`."""
    if len(sys.argv) != 3:
        sys.exit(usage)
    with open(sys.argv[1]) as f:
        data = json.load(f)
    fig = drawers[data["figure"]](data)
    fig.savefig(sys.argv[2], dpi=110)
