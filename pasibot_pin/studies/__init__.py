"""The analyses as library functions returning typed results.

Spring fit, spring study, contact, energy and the single motor. The command line only maps
flags to them.
"""
