#!/usr/bin/env python3
"""Validates plan JSON files against docs/plan.schema.json (Debian's python3-jsonschema).

Usage: validate_plans.py SCHEMA PLAN.json... ; exits 1 naming every file that does not validate.
A plan that must NOT validate can be given after --invalid (checks the schema can fail)."""
import json
import sys

import jsonschema

schema = json.load(open(sys.argv[1]))
validator = jsonschema.Draft202012Validator(schema)
expect_valid, failures, checked = True, 0, 0
for path in sys.argv[2:]:
    if path == "--invalid":
        expect_valid = False
        continue
    errors = list(validator.iter_errors(json.load(open(path))))
    checked += 1
    if bool(errors) == expect_valid:
        failures += 1
        print(f"{path}: {'invalid: ' + errors[0].message if errors else 'validated but should not'}")
print(f"{checked - failures} passed, {failures} failed")
sys.exit(1 if failures else 0)
