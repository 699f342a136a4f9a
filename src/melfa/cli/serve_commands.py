"""`melfa serve`: the web IDE (being built)."""
