import pytest


@pytest.fixture(autouse=True, scope="session")
def _specimen_cache(tmp_path_factory):
    """Keep test specimens out of the user's cache."""
    mp = pytest.MonkeyPatch()
    mp.setenv("ROCKCAL_CACHE", str(tmp_path_factory.mktemp("specimens")))
    yield
    mp.undo()
