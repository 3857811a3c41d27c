"""The dialects of VAL, one package each (docs/ARCHITECTURE.md, "Adding a dialect")."""
