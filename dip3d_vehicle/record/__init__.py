"""What a run records: ``run.mcap`` (Foxglove-readable), ``mav.tlog`` and the annotated video."""
