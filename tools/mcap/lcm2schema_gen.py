#!/usr/bin/env python3
"""lcm2schema_gen: one JSON schema per tandem LCM type, for MCAP files.

Reads the message definitions (lcmtypes/*.lcm) with the parser that
generates the CSV printers (tools/lcm2csv_gen.py), so both tools see the
same fields, and writes OUT_DIR/tandem_schemas.json: {type name: JSON
schema}. The schemas describe the JSON that tandem-log2mcap writes:
field names as in the .lcm file, arrays as JSON arrays (fixed-size ones
with their exact length), nested structs as objects. A float that is not
finite has no JSON number, so it is written as null and the schema allows
null for every float.

    lcm2schema_gen.py OUT_DIR FILE.lcm...
"""
import json
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from lcm2csv_gen import parse  # noqa: E402

SCALARS = {
    "int8_t": {"type": "integer"}, "int16_t": {"type": "integer"},
    "int32_t": {"type": "integer"}, "int64_t": {"type": "integer"},
    "byte": {"type": "integer"}, "boolean": {"type": "boolean"},
    "float": {"type": ["number", "null"]}, "double": {"type": ["number", "null"]},
    "string": {"type": "string"},
}


def field_schema(structs, ftype, dims):
    if dims:
        inner = field_schema(structs, ftype, dims[1:])
        s = {"type": "array", "items": inner}
        if isinstance(dims[0], int):
            s["minItems"] = s["maxItems"] = dims[0]
        return s
    if ftype in SCALARS:
        return dict(SCALARS[ftype])
    return struct_schema(structs, ftype)


def struct_schema(structs, name):
    fields = structs[name]
    return {"type": "object", "title": name,
            "properties": {f: field_schema(structs, t, d) for t, f, d in fields},
            "required": [f for _, f, _ in fields]}


def main():
    out, files = sys.argv[1], sys.argv[2:]
    structs, package = {}, None
    for f in files:
        with open(f) as fh:
            package, s = parse(fh.read())
        structs.update(s)
    schemas = {}
    for name in sorted(structs):
        s = struct_schema(structs, name)
        s["$schema"] = "https://json-schema.org/draft/2020-12/schema"
        s["title"] = f"{package}.{name}"
        schemas[name] = s
    with open(os.path.join(out, "tandem_schemas.json"), "w") as fh:
        json.dump(schemas, fh, indent=1, sort_keys=True)


if __name__ == "__main__":
    main()
