"""A campaign priced before it runs: the first screen and `--dry-run` (`screen`), this
machine's engine speed (`engine_speed`) and the specimens' grain limits (`sizes`)."""
