"""Arguments shared by several sub-commands: the instance (example, data file, overrides)."""
from __future__ import annotations

import json

from ..errors import InputError


def add_instance_arguments(parser) -> None:
    parser.add_argument("theorem", help="theorem id, e.g. wang_l2linf.thm3 (see `lmidsl list`)")
    parser.add_argument("--example", help="a named example of the theorem")
    parser.add_argument("--data", metavar="FILE.json",
                        help="all data and parameters as one JSON object (matrices as nested lists)")
    parser.add_argument("--set", dest="overrides", action="append", default=[], metavar="NAME=VALUE",
                        help="override one parameter or matrix; VALUE is JSON (e.g. rbar=0.6, E=[[1],[0]])")


def parse_overrides(items: list[str]) -> dict:
    out = {}
    for item in items:
        name, sep, text = item.partition("=")
        if not sep or not name:
            raise InputError(f"--set {item!r}: expected NAME=VALUE")
        try:
            out[name.strip()] = json.loads(text)
        except json.JSONDecodeError:
            raise InputError(f"--set {name}: value {text!r} is not JSON (numbers, or matrices as [[...]])") from None
    return out


def load_data_file(path: str | None) -> dict | None:
    if path is None:
        return None
    try:
        with open(path) as fh:
            data = json.load(fh)
    except OSError as exc:
        raise InputError(f"--data {path}: {exc.strerror}") from None
    except json.JSONDecodeError as exc:
        raise InputError(f"--data {path}: not valid JSON ({exc.msg} at line {exc.lineno})") from None
    if not isinstance(data, dict):
        raise InputError(f"--data {path}: expected a JSON object of names to values")
    return data


def instance_spec(args) -> dict:
    """Keyword arguments for :func:`lmidsl.pipeline.make_instance` from parsed arguments."""
    return {"example": args.example, "data": load_data_file(args.data),
            "overrides": parse_overrides(args.overrides)}


def print_json(obj) -> None:
    print(json.dumps(obj, indent=2, default=float))
