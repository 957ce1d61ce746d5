"""Parametric generators of masonry structures, each returning a ``blockscene/1`` dict."""
