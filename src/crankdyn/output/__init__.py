"""The one path from a scene to its files (:mod:`crankdyn.output.pipeline`), the writers of
results.json, CSV and XLSX (:mod:`crankdyn.output.writers`) and the manifest of the files
crankdyn wrote (:mod:`crankdyn.output.manifest`)."""
