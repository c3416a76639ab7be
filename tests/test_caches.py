"""The one per-object cache: keyed by identity and a key, bounded, never fooled by a reused id."""

import pytest

from pasibot_pin.caches import PerObjectCache


class Owner:
    pass


def test_hit_miss_and_key():
    cache: PerObjectCache[int] = PerObjectCache(size=4)
    owner, calls = Owner(), []
    build = lambda: calls.append(1) or len(calls)  # noqa: E731
    assert cache.get(owner, build, "a") == 1
    assert cache.get(owner, build, "a") == 1
    assert cache.get(owner, build, "b") == 2
    assert cache.get(Owner(), build, "a") == 3  # another owner, same key: its own entry


def test_bounded_oldest_first_and_fresh():
    cache: PerObjectCache[int] = PerObjectCache(size=2)
    owners = [Owner() for _ in range(3)]
    for k, owner in enumerate(owners):
        cache.get(owner, lambda k=k: k)
    assert len(cache) == 2
    assert cache.get(owners[0], lambda: 99) == 99  # dropped, rebuilt
    assert cache.get(owners[2], lambda: -1) == 2
    assert cache.get(owners[2], lambda: 7, fresh=lambda v: v != 2) == 7  # stale: rebuilt in place
    assert len(cache) == 2


def test_entry_keeps_its_owner():
    cache: PerObjectCache[str] = PerObjectCache(size=8)
    owner = Owner()
    cache.get(owner, lambda: "first")
    ident = id(owner)
    del owner  # the entry holds it: no new object can take its id while the entry lives
    assert all(id(Owner()) != ident for _ in range(100))
    with pytest.raises(ValueError):
        PerObjectCache(size=0)
