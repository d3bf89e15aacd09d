"""PFC's files of a calibration, in PFC2D and PFC3D: FISHTank's parameter file
(`parameter_file`: `.p2dat`, PFC3D's `mpParams.p3dat`), the same values as a script for PFC's
`itasca` Python (`python_script`) or as JSON (`json_file`), and a specimen's ball and bond lists
(`specimen_lists`); the writers by format name in `formats`.

The formats are PFC's and FISHTank's (Itasca's FISH material-genesis package), not rockcal's:
rockcal writes them itself, in the layout and names of FISHTank's own example files, so that a
PFC project reads a calibration as it reads FISHTank's. The writers take a `Calibrated` record
(`calibrated`): what a campaign identified, handed down; nothing here reads a campaign."""
