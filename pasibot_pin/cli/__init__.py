"""Subcommands of the ``pasibot`` CLI: one module each, with ``register(subparsers)``.

To add a subcommand, add a module here and its name to :data:`COMMANDS`.
"""

COMMANDS: list[str] = [
    "info",
    "build_urdf",
    "analyze",
    "view",
    "export_html",
    "export_mjcf",
    "gait",
    "torques",
    "simulate",
    "walk",
    "contact",
    "energy",
    "sweep",
    "optimize",
    "find_walker",
]
