"""rockcal has numba compile for 512-bit vectors on a processor with AVX-512, and only where the
user chose no processor of their own (`rockcal.wide_vectors`); that the numbers do not change
with the width is `tests/dem/test_portable.py`'s."""

import os

import pytest
from llvmlite import binding

from rockcal.wide_vectors import NO_256_BIT_PREFERENCE, USERS_OWN, prefer_512_bit_vectors


def test_the_processors_features_without_the_256_bit_preference_where_it_has_avx512(monkeypatch):
    for name in USERS_OWN:
        monkeypatch.delenv(name, raising=False)
    host = binding.get_host_cpu_features().flatten()
    has_avx512 = "+avx512f" in host.split(",")
    assert prefer_512_bit_vectors() == has_avx512
    assert os.environ.get("NUMBA_CPU_FEATURES") == (f"{host},{NO_256_BIT_PREFERENCE}" if has_avx512 else None)


@pytest.mark.parametrize("setting", [("NUMBA_CPU_NAME", "generic"), ("NUMBA_ENABLE_AVX", "0")])
def test_a_users_own_processor_setting_is_kept(monkeypatch, setting):
    for name in USERS_OWN:
        monkeypatch.delenv(name, raising=False)
    monkeypatch.setenv(*setting)
    assert not prefer_512_bit_vectors()
    assert "NUMBA_CPU_FEATURES" not in os.environ
