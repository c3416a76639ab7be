"""Numerical methods the studies use: shooting on a step map, statics, spring fits, validation cases."""
