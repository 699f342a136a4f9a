"""`melfa upload|run|stop|delete|exec|pose|hand|servo|jog` (being built)."""
