"""`melfa desktop`: the small Qt client (being built)."""
