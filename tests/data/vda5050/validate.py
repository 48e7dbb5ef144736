#!/usr/bin/env python3
"""Validates JSON messages against a JSON Schema (draft 2020-12) with Debian's python3-jsonschema,
an implementation independent of fleetloc. Usage: validate.py SCHEMA MESSAGE.json...
Exit 0 when every message is valid; 1 with one line per invalid message on stderr."""
import json
import sys

import jsonschema


def main() -> int:
    with open(sys.argv[1], encoding="utf-8") as f:
        schema = json.load(f)
    jsonschema.Draft202012Validator.check_schema(schema)
    validator = jsonschema.Draft202012Validator(schema, format_checker=jsonschema.FormatChecker())
    failed = 0
    for path in sys.argv[2:]:
        with open(path, encoding="utf-8") as f:
            message = json.load(f)
        for error in validator.iter_errors(message):
            print(f"{path}: {'/'.join(map(str, error.path)) or '(top)'}: {error.message}",
                  file=sys.stderr)
            failed = 1
    return failed


if __name__ == "__main__":
    sys.exit(main())
