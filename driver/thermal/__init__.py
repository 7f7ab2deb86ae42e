"""The thermal macro scale of the flash-temperature extension (thesis ch. 8)."""
