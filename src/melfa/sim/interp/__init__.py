"""MELFA BASIC IV interpreter for the virtual controller (being built)."""
