"""sim2d package."""
