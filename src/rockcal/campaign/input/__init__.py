"""The campaign file: its sections and checks (`config`), the lab's targets by test
(`targets`), its raw numbers checked before the schema (`raw_values`), and the embedded rocks'
campaign files (`granite.toml`, `ldb.toml`)."""
