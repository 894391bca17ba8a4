"""The checkpoint key (motionsig_cli.checkpoint_key): made once per account, owner-only, checked before use."""

import os
import stat

import pytest

from motionsig_cli import checkpoint_key as ck
from motionsig_cli.errors import InputError


@pytest.fixture
def home(tmp_path, monkeypatch):
    monkeypatch.delenv(ck.KEY_ENV, raising=False)
    monkeypatch.setenv("XDG_CONFIG_HOME", str(tmp_path))
    monkeypatch.setattr(ck, "_cached", {})
    return tmp_path / "motionsig" / ck.KEY_FILE


def test_the_key_file_is_made_once_owner_only_and_reused(home, monkeypatch):
    key = ck.checkpoint_key()
    assert ck.key_path() == home and home.is_file()
    assert stat.S_IMODE(home.stat().st_mode) == 0o600
    assert len(key) == 64 and int(key, 16) >= 0
    monkeypatch.setattr(ck, "_cached", {})
    assert ck.checkpoint_key() == key  # read back, not made anew
    monkeypatch.setenv(ck.KEY_ENV, "shared")
    assert ck.checkpoint_key() == b"shared"


def test_two_accounts_get_two_keys(tmp_path, monkeypatch):
    monkeypatch.delenv(ck.KEY_ENV, raising=False)
    keys = []
    for who in ("a", "b"):
        monkeypatch.setenv("XDG_CONFIG_HOME", str(tmp_path / who))
        monkeypatch.setattr(ck, "_cached", {})
        keys.append(ck.checkpoint_key())
    assert keys[0] != keys[1]


@pytest.mark.parametrize(
    ("make", "match"),
    [
        (lambda p: p.mkdir(), "not a regular file"),
        (lambda p: (p.write_text("0" * 64), os.chmod(p, 0o666)), "may be written by others"),
        (lambda p: (p.write_text("not hex at all"), os.chmod(p, 0o600)), "not 64 hex digits"),
        (lambda p: (p.write_text("0" * 10_000), os.chmod(p, 0o600)), "10000 bytes"),
        (lambda p: p.symlink_to(p), "not a regular file"),
    ],
)
def test_a_bad_key_file_is_refused_by_name(home, make, match):
    home.parent.mkdir(parents=True)
    make(home)
    with pytest.raises(InputError, match=match) as exc:
        ck.checkpoint_key()
    assert str(home) in str(exc.value)
