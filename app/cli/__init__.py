"""The `frost` command (pyproject's console script); the subcommand CLI replaces this."""


def main(argv: list[str] | None = None) -> int:
    # Imported on call: app.__main__ imports app.cli.options, so a module-level import
    # here would be circular whenever app.__main__ is imported first.
    from app.__main__ import main as run

    return run(argv)
