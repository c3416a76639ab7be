"""The engine twin: the same walk in MuJoCo, on the model the package exports."""
