"""Reading a TOML file safely, and showing its keys and values in a message: the file's
size and nesting bounded (:func:`read_toml`), keys and texts printable names and texts
(:func:`text_problem`), a key path, a file path and a value cut and escaped for one line of
message (:func:`shown_key`, :func:`shown_path`, :func:`shown`). What every file reader of
beltcalc (:mod:`beltcalc.data.schema`) stands on; pint and TOML are not imported here.
"""

from __future__ import annotations

import os

from beltcalc.errors import CatalogError

MAX_DEPTH = 32                  # tables and arrays in tables and arrays: the catalogs need 4
MAX_FILE_BYTES = 20_000_000     # a catalog, scene or drive file; the largest built-in is ~30 kB
MAX_NAME = 100                  # characters of a name (manufacturer, profile, motor, ...)
MAX_TEXT = 10_000               # characters of any other text (a note, a source)


# --- the file: bytes, depth, keys, and how messages show them ----------------------------------
def quote(text, limit: int = 40) -> str:
    """``repr(text)``, cut to its first ``limit`` characters for a message (control and
    direction characters escaped by ``repr``).

    >>> quote("50 kg"), quote("9" * 400)
    ("'50 kg'", "'9999999999999999999999999999999999999999'... (400 characters)")
    """
    text = str(text)
    if len(text) <= limit:
        return repr(text)
    return f"{text[:limit]!r}... ({len(text)} characters)"


def shown(raw, limit: int = 40) -> str:
    """A raw value as a message shows it: a text quoted (:func:`quote`), anything else as
    Python writes it, cut to ``limit`` characters.

    >>> shown("5 kg"), shown(3), shown([1] * 30)
    ("'5 kg'", '3', '[1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, ... (90 characters)')
    """
    if isinstance(raw, str):
        return quote(raw, limit)
    text = repr(raw)
    return text if len(text) <= limit else f"{text[:limit]}... ({len(text)} characters)"


def shown_key(key: str, limit: int = 40) -> str:
    r"""A key path as a message shows it: every part cut to ``limit`` characters and every
    character that is not printable (a newline, a right-to-left override) escaped.

    >>> shown_key("belts[0]." + "x" * 100_000), shown_key("a\u202eb.c")
    ('belts[0].xxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxx... (100000 characters)', 'a\\u202eb.c')
    """
    parts = []
    for part in str(key).split("."):
        cut = part[:limit] + f"... ({len(part)} characters)" if len(part) > limit else part
        parts.append("".join(c if c.isprintable() else repr(c)[1:-1] for c in cut))
    return ".".join(parts)


def shown_path(path, limit: int = 200) -> str:
    """A file path as a message shows it: characters that are not printable escaped, cut
    to ``limit`` characters (the line stays one line).

    >>> print(shown_path("my\\ncatalog.toml"))
    my\\ncatalog.toml
    """
    text = "".join(c if c.isprintable() else repr(c)[1:-1] for c in str(path))
    return text if len(text) <= limit else f"{text[:limit]}... ({len(text)} characters)"


def text_problem(text: str, name: bool = False) -> str:
    r"""Why ``text`` cannot stand in a file ("" if it can): a control or formatting
    character (a newline in a name, a right-to-left override anywhere, which would make a
    table or a message say something else than the file), or a text too long.

    >>> text_problem("BRECO"), text_problem("AT\u202e01", name=True)
    ('', "'AT\\u202e01' holds the character U+202E; names are printable text on one line")
    """
    import unicodedata

    limit = MAX_NAME if name else MAX_TEXT
    if len(text) > limit:
        return f"{quote(text)} is too long (at most {limit} characters)"
    allowed = "" if name else "\n\t"
    for c in text:
        if c not in allowed and unicodedata.category(c) in ("Cc", "Cf", "Cs", "Co", "Cn", "Zl", "Zp"):
            what = "names are printable text on one line" if name else "texts are printable (newlines and tabs allowed)"
            return f"{quote(text)} holds the character U+{ord(c):04X}; {what}"
    if name and text != text.strip():
        return f"{quote(text)} starts or ends with a space"
    return ""


def read_toml(path: str | os.PathLike, what: str = "catalog file") -> dict:
    """The TOML file ``path`` as a dict, or a :class:`CatalogError` naming the file: missing,
    unreadable, not UTF-8, not TOML, too large (:data:`MAX_FILE_BYTES`) or nested deeper
    than :data:`MAX_DEPTH` (a 5,000-level array would exhaust Python's recursion)."""
    import tomllib

    label = shown_path(path)
    try:
        size = os.stat(path).st_size
        if size > MAX_FILE_BYTES:
            raise CatalogError(f"{label}: {size} bytes; a {what} has at most {MAX_FILE_BYTES} bytes")
        with open(path, "rb") as fh:
            raw = fh.read()
        # a byte-order mark (Windows editors save one) is no part of the TOML
        data = tomllib.loads(raw.decode("utf-8-sig"))
    except FileNotFoundError:
        raise CatalogError(f"{what} {label} does not exist") from None
    except tomllib.TOMLDecodeError as exc:
        raise CatalogError(f"{label}: not valid TOML ({exc})") from None
    except UnicodeDecodeError as exc:
        raise CatalogError(f"{label}: not UTF-8 text (byte {exc.start}); save it as UTF-8") from None
    except (RecursionError, MemoryError):
        raise CatalogError(f"{label}: nested too deeply (more than {MAX_DEPTH} levels of tables and arrays)") \
            from None
    except OSError as exc:
        raise CatalogError(f"{label}: cannot be read ({exc.strerror})") from None
    _check_depth(label, data)
    return data


def _check_depth(label: str, data: dict) -> None:
    """Refuse tables and arrays nested deeper than :data:`MAX_DEPTH` (iteratively), and keys
    with control characters or longer than :data:`MAX_NAME` characters, naming the key."""
    stack = [(data, 1, "")]
    while stack:
        node, depth, where = stack.pop()
        if depth > MAX_DEPTH:
            raise CatalogError(f"{label}: {shown_key(where)}: nested too deeply (more than {MAX_DEPTH} levels "
                               "of tables and arrays)")
        items = node.items() if isinstance(node, dict) else enumerate(node)
        for key, value in items:
            if isinstance(key, str):
                problem = text_problem(key, name=True)
                if problem:
                    raise CatalogError(f"{label}: {shown_key(join(where, key))}: key {problem}")
                inner = join(where, key)
            else:
                inner = f"{where}[{key}]"
            if isinstance(value, (dict, list)):
                stack.append((value, depth + 1, inner))


def join(at: str, key: str) -> str:
    """The path of ``key`` inside the table at ``at`` (``""``: the top of the file).

    >>> join("", "source"), join("belts[0]", "pitch")
    ('source', 'belts[0].pitch')
    """
    return f"{at}.{key}" if at else key
