from app.__main__ import main  # noqa: F401  (the `frost` console script; the subcommand CLI replaces this)
