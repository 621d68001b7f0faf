"""An independent reader of the MCAP files `audit --format mcap` writes:
Foxglove's `mcap` package reads them, and every message is checked against
Foxglove's own JSON schemas (docs/schemas/external/foxglove/, from npm
`@foxglove/schemas` 2.1.0; SOURCES.md there gives their sha256, checked here
first so that an edited schema cannot pass).

For every channel whose schema is `foxglove.*`:
  * schema encoding `jsonschema`, message encoding `json`;
  * the schema in the file is Foxglove's (the same JSON);
  * every message is UTF-8 JSON valid under it (Draft 2020-12, the
    validator's default for a schema without `$schema`), and has no null
    (a NaN written by serde_json);
  * what JSON Schema leaves open: base64 data decodes, a PointCloud's data
    is `point_stride` times its points and every field fits in the stride,
    `nsec` below 1e9, quaternions of unit length.

For every channel whose schema is `extrinsic_audit.*` (this tool's own,
docs/schemas/mcap/): the schema in the file is the committed one, it is
one that Foxglove's and Lichtblick's JSON-schema reader takes (`viewer_
readable`: one `type` per field, no `null`, typed array items, objects
all the way down: what that reader, parseJsonSchema in their mcap-support
package, accepts; a `null` type or a list of types there stops the file
from opening), and every message is valid under it and holds no null.

`read(path)` returns the messages decoded, by topic, with the channels'
encodings and the file's metadata records.
"""
import base64
import hashlib
import json
import math
import re
import struct
from pathlib import Path

from jsonschema import Draft202012Validator
from mcap.reader import make_reader

ROOT = Path(__file__).resolve().parent.parent
SCHEMAS = ROOT / "docs" / "schemas" / "external" / "foxglove"
OWN_SCHEMAS = ROOT / "docs" / "schemas" / "mcap"
VIEWER_TYPES = {"boolean", "string", "number", "integer", "object", "array"}

# foxglove.NumericType: byte size and struct code.
NUMERIC = {1: (1, "B"), 2: (1, "b"), 3: (2, "H"), 4: (2, "h"), 5: (4, "I"),
           6: (4, "i"), 7: (4, "f"), 8: (8, "d")}


class Invalid(Exception):
    """A file or message that breaks Foxglove's contract."""


def schema_sha256s():
    """The sha256 SOURCES.md gives for each committed schema file."""
    text = (SCHEMAS / "SOURCES.md").read_text()
    return dict(re.findall(r"\| `(\w+\.json)` \| `([0-9a-f]{64})` \|", text))


def check_schema_files():
    """Every committed schema file is as SOURCES.md lists it."""
    listed = schema_sha256s()
    present = sorted(p.name for p in SCHEMAS.glob("*.json"))
    if sorted(listed) != present:
        raise Invalid(f"SOURCES.md lists {sorted(listed)}, the folder holds {present}")
    for name, digest in listed.items():
        got = hashlib.sha256((SCHEMAS / name).read_bytes()).hexdigest()
        if got != digest:
            raise Invalid(f"{name}: sha256 {got}, SOURCES.md says {digest}")


def _walk(o, path, name):
    if o is None:
        raise Invalid(f"{name}: null at {path} (a non-finite number?)")
    if isinstance(o, dict):
        if set(o) == {"sec", "nsec"} and not 0 <= o["nsec"] < 1_000_000_000:
            raise Invalid(f"{name}: nsec out of range at {path}: {o}")
        if set(o) == {"x", "y", "z", "w"}:
            n = math.sqrt(sum(o[k] ** 2 for k in "xyzw"))
            if abs(n - 1) > 1e-9:
                raise Invalid(f"{name}: quaternion at {path} has |q| = {n}")
        for k, v in o.items():
            _walk(v, f"{path}.{k}", name)
    elif isinstance(o, list):
        for i, v in enumerate(o):
            _walk(v, f"{path}[{i}]", name)


def viewer_readable(schema, path="$"):
    """Raise Invalid where Foxglove's JSON-schema reader would refuse
    `schema` (an object schema): every property one type of VIEWER_TYPES,
    array items one non-array type, nested objects likewise."""
    if schema.get("type") != "object":
        raise Invalid(f"{path}: expected type object, found {schema.get('type')!r}")
    for name, field in schema.get("properties", {}).items():
        where = f"{path}.{name}"
        t = field.get("type")
        if not isinstance(t, str) or t not in VIEWER_TYPES:
            raise Invalid(f"{where}: the viewer takes one type of {sorted(VIEWER_TYPES)}, found {t!r}")
        if t == "object":
            viewer_readable(field, where)
        if t == "array":
            item = field.get("items", {})
            it = item.get("type")
            if not isinstance(it, str) or it not in VIEWER_TYPES - {"array"}:
                raise Invalid(f"{where}[]: the viewer takes one non-array item type, found {it!r}")
            if it == "object":
                viewer_readable(item, where + "[]")


def _validator(schema, topic):
    """The validator of a channel's schema: Foxglove's own file, or this
    tool's (checked readable by the viewer)."""
    foxglove = schema.name.startswith("foxglove.")
    folder, name = (SCHEMAS, schema.name.split(".", 1)[1]) if foxglove else (OWN_SCHEMAS, schema.name.split(".", 1)[1])
    ref = json.loads((folder / (name + ".json")).read_text())
    if json.loads(schema.data) != ref:
        raise Invalid(f"{topic}: the schema in the file is not the committed {schema.name}")
    Draft202012Validator.check_schema(ref)
    if not foxglove:
        viewer_readable(ref)
    return Draft202012Validator(ref)


def decode_cloud(msg):
    """A PointCloud's points as a list of dicts, field name -> value."""
    raw = base64.b64decode(msg["data"], validate=True)
    stride = msg["point_stride"]
    if stride <= 0 or len(raw) % stride:
        raise Invalid(f"PointCloud: {len(raw)} bytes is not a multiple of stride {stride}")
    fields = []
    for f in msg["fields"]:
        size, code = NUMERIC.get(f["type"], (None, None))
        if size is None or f["offset"] + size > stride:
            raise Invalid(f"PointCloud: field {f['name']} does not fit the stride")
        fields.append((f["name"], f["offset"], "<" + code))
    return [{n: struct.unpack_from(c, raw, i + o)[0] for n, o, c in fields}
            for i in range(0, len(raw), stride)]


def read(path):
    """Every message of `path`, validated; see the module docs."""
    check_schema_files()
    validators, topics = {}, {}
    with open(path, "rb") as f:
        reader = make_reader(f)
        for schema, channel, message in reader.iter_messages():
            t = topics.setdefault(channel.topic, {
                "schema": schema.name if schema else None,
                "schema_encoding": schema.encoding if schema else None,
                "message_encoding": channel.message_encoding,
                "messages": [], "log_times": []})
            msg = json.loads(message.data.decode("utf-8"))
            t["messages"].append(msg)
            t["log_times"].append(message.log_time)
            if schema is None or not schema.name.startswith(("foxglove.", "extrinsic_audit.")):
                continue
            if (schema.encoding, channel.message_encoding) != ("jsonschema", "json"):
                raise Invalid(f"{channel.topic}: {schema.encoding}/{channel.message_encoding}")
            if schema.name not in validators:
                validators[schema.name] = _validator(schema, channel.topic)
            errors = sorted(validators[schema.name].iter_errors(msg), key=str)
            if errors:
                e = errors[0]
                raise Invalid(f"{channel.topic}: {e.message} at {list(e.absolute_path)}")
            _walk(msg, channel.topic, schema.name)
            if schema.name == "foxglove.PointCloud":
                decode_cloud(msg)
        metadata = {m.name: dict(m.metadata) for m in reader.iter_metadata()}
    return {"topics": topics, "metadata": metadata}
