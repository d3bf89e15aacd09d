"""rockcal's version: part of every stored run's key and of every snapshot, so runs and
snapshots of another version are made again (CHANGELOG.md)."""

__version__ = "0.2.1"
