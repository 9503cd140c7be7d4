#!/usr/bin/env python3
"""Writes a JSON file from an example with edits, for the benchmark scripts:
edit_json.py SRC DST PYTHON-STATEMENTS (run on the parsed document `d`)."""
import json
import sys

d = json.load(open(sys.argv[1]))
exec(sys.argv[3])
json.dump(d, open(sys.argv[2], "w"), indent=2)
