#!/usr/bin/env python3
"""The model format's JSON Schema (config/schema/volcomp-model-1.schema.json) against the
examples, with python3-jsonschema from Debian: the schema is itself valid (Draft 2020-12),
every example model and the model of docs/model-file.md is valid under it, and files volcomp's
reader refuses for their shape (a missing error_units, an unknown key or component, a bad
interpolation, a string where a number belongs) are invalid under it too. volcomp's reader stays
the authority; this keeps the schema from drifting from it.
Usage: schema_test.py SCHEMA EXAMPLES_DIR DOCS_MODEL_FILE_MD"""
import copy
import json
import pathlib
import re
import sys

import jsonschema

schema_path, examples, doc = (pathlib.Path(p) for p in sys.argv[1:4])
schema = json.loads(schema_path.read_text())
jsonschema.Draft202012Validator.check_schema(schema)
validator = jsonschema.Draft202012Validator(schema)
failures = []


def expect(valid, document, what):
    errors = list(validator.iter_errors(document))
    if valid and errors:
        failures.append(f"{what}: expected valid, got {errors[0].message[:200]}")
    if not valid and not errors:
        failures.append(f"{what}: expected invalid, the schema accepts it")


models = []
for path in sorted(examples.glob("*.json")):
    document = json.loads(path.read_text())
    if document.get("format") != "volcomp-model/1" or "identify" in path.read_text():
        continue  # daemon and simulator configurations; calibration templates
    models.append(path.name)
    expect(True, document, path.name)
if len(models) < 4:
    failures.append(f"expected at least 4 example models, found {models}")

# The complete example of docs/model-file.md ("The whole file").
blocks = re.findall(r"```json\n(.*?)```", doc.read_text(), re.S)
whole = [json.loads(b) for b in blocks if b.lstrip().startswith("{") and '"format"' in b]
if not whole:
    failures.append("no complete model in docs/model-file.md")
for i, document in enumerate(whole):
    expect(True, document, f"docs/model-file.md model {i}")

vmc = json.loads((examples / "vmc-xyfz-21.json").read_text())
refused = {
    "no error_units": lambda m: m.pop("error_units"),
    "unknown key": lambda m: m.update(colour="red"),
    "unknown component": lambda m: m["components"].update(EQX=1.0),
    "bad interpolation": lambda m: m["components"]["EXX"].update(interpolation="spline"),
    "string value": lambda m: m["components"].update(EC0Y="18.5"),
    "bad topology": lambda m: m.update(topology="XYZ"),
    "bad length unit": lambda m: m["error_units"].update(length="inch"),
}
for what, change in refused.items():
    document = copy.deepcopy(vmc)
    change(document)
    expect(False, document, what)

for failure in failures:
    print("FAIL", failure)
print(f"{len(models)} example models, {len(whole)} documented model(s), {len(refused)} refusals")
sys.exit(1 if failures else 0)
