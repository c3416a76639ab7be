"""Figures (``ax=None``, return the figure), the meshcat viewer, HTML export and GIF animation."""
