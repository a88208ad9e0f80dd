"""wall_truth: truths for rockwatch from an engine independent of its model (see tests/truth/README.md)."""
