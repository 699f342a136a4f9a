"""`melfa users …`: accounts and lab groups (being built)."""
