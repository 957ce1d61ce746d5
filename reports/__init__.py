"""The validation run over the scene catalog and the comparison report."""
