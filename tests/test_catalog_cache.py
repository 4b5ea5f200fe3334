"""The parsed built-in catalogs kept in the user's cache (beltcalc/data/catalogs.py,
``_builtin_catalog``): the same entries as reading the files, never stale, never in the way."""

from __future__ import annotations

import pickle
import shutil

import pytest

import beltcalc.data.catalogs as catalogs
from beltcalc.data.catalogs import CACHE_ENV, load_catalog

ORIGINAL_DIR = catalogs.builtin_dir


def summary(cat) -> dict:
    """Every entry's name and a few numbers, and the files read."""
    out = {"files": list(cat.files)}
    for kind in ("belts", "threads", "motors", "chains"):
        out[kind] = sorted(getattr(cat, kind))
    out["AT10"] = cat.belt("AT10").width_row(0.025).F_Tadm
    out["10B-1"] = (cat.chain("10B-1").pitch, cat.chain("10B-1").breaking_load)
    return out


def fresh(monkeypatch, tmp_path) -> None:
    monkeypatch.setenv(CACHE_ENV, str(tmp_path / "cache"))


def test_the_cache_gives_what_the_files_give(monkeypatch, tmp_path):
    monkeypatch.setenv(CACHE_ENV, "off")
    from_files = summary(load_catalog())
    fresh(monkeypatch, tmp_path)
    first = load_catalog()                     # reads the files, writes the cache
    written = list((tmp_path / "cache").glob("catalog-*.pickle"))
    assert len(written) == 1
    assert list((tmp_path / "cache").glob("*.tmp")) == []
    second = load_catalog()                    # from the cache
    assert summary(first) == from_files
    assert summary(second) == from_files
    assert second is not first and second.belts["breco-at10"] is not first.belts["breco-at10"]


def test_a_catalog_with_extra_files_does_not_touch_the_cache(monkeypatch, tmp_path):
    fresh(monkeypatch, tmp_path)
    load_catalog()
    cached = next((tmp_path / "cache").glob("catalog-*.pickle")).read_bytes()
    user = tmp_path / "mine.toml"
    user.write_text('units = { d = "mm", P = "mm", d2 = "mm", flank_angle = "deg" }\n'
                    '[source]\ndocument = "test"\n'
                    '[[threads]]\nname = "M99"\nseries = "coarse"\nd = 99.0\nP = 9.0\nd2 = 93.155\n'
                    'flank_angle = 60\n', encoding="utf-8")
    with_user = load_catalog([user])
    assert "m99" in with_user.threads
    assert with_user.thread("M99").d2 == pytest.approx(0.093155)
    assert next((tmp_path / "cache").glob("catalog-*.pickle")).read_bytes() == cached
    assert "m99" not in load_catalog().threads


def test_a_broken_cache_file_is_read_around_and_replaced(monkeypatch, tmp_path):
    fresh(monkeypatch, tmp_path)
    load_catalog()
    cache = next((tmp_path / "cache").glob("catalog-*.pickle"))
    cache.write_bytes(b"not a pickle")
    assert summary(load_catalog())["AT10"] == pytest.approx(2200.0)
    assert pickle.loads(cache.read_bytes()).belt("AT10").width_row(0.025).F_Tadm == pytest.approx(2200.0)


def test_an_edited_catalog_file_is_never_read_from_a_stale_cache(monkeypatch, tmp_path):
    root = tmp_path / "catalogs"
    shutil.copytree(catalogs.builtin_dir(), root)
    monkeypatch.setattr(catalogs, "builtin_dir", lambda: root)
    fresh(monkeypatch, tmp_path)
    assert load_catalog().belt("AT10").width_row(0.025).F_Tadm == pytest.approx(2200.0)
    path = root / "belts" / "breco_at10.toml"
    text = path.read_text(encoding="utf-8")
    assert text.count("2200") == 1
    path.write_text(text.replace("2200", "2100"), encoding="utf-8")
    assert load_catalog().belt("AT10").width_row(0.025).F_Tadm == pytest.approx(2100.0)
    assert len(list((tmp_path / "cache").glob("catalog-*.pickle"))) == 1     # the older version replaced
    monkeypatch.setattr(catalogs, "builtin_dir", ORIGINAL_DIR)
    load_catalog()                                                           # another folder: its own file
    assert len(list((tmp_path / "cache").glob("catalog-*.pickle"))) == 2
    monkeypatch.setattr(catalogs, "builtin_dir", lambda: root)
    assert all(str(root) in f for f in load_catalog().files)


def test_no_cache_where_it_is_off_or_cannot_be_written(monkeypatch, tmp_path):
    monkeypatch.setenv(CACHE_ENV, "off")
    assert summary(load_catalog())["AT10"] == pytest.approx(2200.0)
    blocked = tmp_path / "file"
    blocked.write_text("a file where the cache folder would be")
    monkeypatch.setenv(CACHE_ENV, str(blocked / "cache"))
    assert summary(load_catalog())["AT10"] == pytest.approx(2200.0)
    assert blocked.read_text() == "a file where the cache folder would be"
