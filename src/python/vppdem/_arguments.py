"""Turning a call's arguments into the engine's: settings dicts and keywords into --set lines
(one TOML literal per key, a key given twice with two values refused), counts checked."""

import json
import math
import os

import numpy as np

from ._native import ConfigError


def _out_folder(name, out):
    """An output folder as given: an empty or blank one is refused (it would be the current
    folder, whose files a run would replace), as the commands refuse --out ''."""
    path = os.fspath(out)
    if not str(path).strip():
        raise ValueError(f"{name} = {path!r}: an empty or blank output folder is refused (it would be the current "
                         "folder, whose files the run would replace); give a folder's path, e.g. 'out/run1'")
    return path


def _literal(key, v):
    """A Python value as the TOML literal `--set key=value` takes."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    if isinstance(v, (float, np.floating)):
        v = float(v)
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)  # shortest text that reads back to the same double
    if isinstance(v, str):
        return json.dumps(v)  # a TOML basic string
    raise ConfigError(f"config key '{key}': cannot use a value of type {type(v).__name__} ({v!r})")


def _same_value(a, b):
    """Whether two values of one key say the same: equal numbers (2 and 2.0), or the same
    literal (True is not 1 here: the readers tell a boolean from an integer)."""
    if isinstance(a, bool) or isinstance(b, bool):
        return isinstance(a, bool) and isinstance(b, bool) and a == b
    if isinstance(a, (int, float, np.integer, np.floating)) and isinstance(b, (int, float, np.integer, np.floating)):
        return a == b or (math.isnan(a) and math.isnan(b))
    try:
        return type(a) is type(b) and bool(a == b)
    except (TypeError, ValueError):  # e.g. arrays (which no key takes): not the same
        return False


def _put(out, key, v, where, first):
    """out[key] = v, refusing a second, different value of the key (`where` names the source of
    v, `first` that of the value already there)."""
    if key in out and not _same_value(out[key], v):
        raise ValueError(f"config key '{key}' given twice with different values: {out[key]!r} ({first[key]}) and "
                         f"{v!r} ({where}); give it once (to override a dict's value, merge it first: "
                         f"settings={{**base, '{key}': value}})")
    if key not in out:
        out[key] = v
        first[key] = where


def _flatten(d, prefix="", where="settings", out=None, first=None):
    """A dict of nested tables and dotted keys as {dotted key: value}; the same key twice (a
    nested table and a dotted key) is refused unless the values agree."""
    out = {} if out is None else out
    first = {} if first is None else first
    for k, v in d.items():
        key = f"{prefix}.{k}" if prefix else str(k)
        if isinstance(v, dict):
            _flatten(v, key, where, out, first)
        else:
            _put(out, key, v, where, first)
    return out


def _dict_argument(name, d):
    """The settings dict `name`, or a TypeError naming what it is instead (a list of pairs, of
    "key=value" strings, ...)."""
    if d is None:
        return {}
    if not isinstance(d, dict):
        raise TypeError(f"{name}: a dict of dotted keys, e.g. {{\"process.underpressure\": 0.06e6}}, not "
                        f"{type(d).__name__} ({d!r:.80})")
    return d


def _sets(config, settings, kwargs):
    """(path of the TOML file or "", the key=value overrides in order). `config` (a file or a
    dict) is the base; `settings` and the keywords override it, and may not disagree with each
    other (a key given in both with two values raises ConfigError)."""
    path, base = "", {}
    if config is None:
        pass
    elif isinstance(config, (str, os.PathLike)):
        path = os.fspath(config)
    elif isinstance(config, dict):
        base = _flatten(config, where="config")
    else:
        raise TypeError(f"config: a TOML file's path or a dict, not {type(config).__name__}")
    values, first = {}, {}
    _flatten(_dict_argument("settings", settings), out=values, first=first)
    for k, v in kwargs.items():
        _put(values, k.replace("__", "."), v, f"keyword {k}", first)
    base.update(values)
    return path, [f"{k}={_literal(k, v)}" for k, v in base.items()]


def _count(name, v, low, high=None, also=""):
    """v as an int, refusing a bool, a non-integer (1.5; int() would cut it) and a value outside
    [low, high], with a message naming `name`, v and what is allowed (`also`: what else is)."""
    import operator

    allowed = f"a whole number >= {low}" + ("" if high is None else f" and <= {high}") + also
    if isinstance(v, bool):
        raise TypeError(f"{name} = {v!r}: {allowed}, not a bool")
    try:
        i = operator.index(v)
    except TypeError:
        if isinstance(v, (float, np.floating)) and math.isfinite(v) and float(v).is_integer():
            i = int(v)  # 3.0 is three
        else:
            raise (ValueError if isinstance(v, (float, np.floating)) else TypeError)(
                f"{name} = {v!r}: {allowed}") from None
    if i < low or (high is not None and i > high):
        raise ValueError(f"{name} = {i}: {allowed}")
    return i


def _study_sets(sets, settings):
    """The fixed overrides of a study: `sets` ("key=value" strings, as --set) and `settings` (a
    dict); a key in both is refused (which one would win is not what either says)."""
    if sets is None:
        sets = []
    if not isinstance(sets, (str, bytes, dict)):
        sets = list(sets)
    if isinstance(sets, (str, bytes, dict)) or not all(isinstance(s, str) for s in sets):
        raise TypeError(f"sets: a list of \"key=value\" strings, as --set takes, not {sets!r:.80}")
    extra = _sets(None, settings, {})[1]
    given = {s.split("=", 1)[0].strip() for s in sets}
    for s in extra:
        key = s.split("=", 1)[0]
        if key in given:
            raise ValueError(f"config key '{key}' given both in sets and in settings; give it once")
    return list(sets) + extra
