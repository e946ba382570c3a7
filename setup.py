"""The wheel carries the shaders and the background image inside `app` (as `app/_data/`).

They live at the checkout's top level (`shaders/`, `assets/`), outside every package, so
package data cannot name them; this build step copies them into the build tree, never into
the checkout. An editable install needs no copy: `app/resources.py` finds the checkout's."""

from pathlib import Path

from setuptools import setup
from setuptools.command.build_py import build_py

HERE = Path(__file__).resolve().parent
# (folder in the checkout, file pattern) -> app/_data/<folder>/ in the wheel
DATA = [("shaders", "*"), ("assets", "background.png"), ("assets", "lockscreen.png")]


class BuildWithData(build_py):
    def run(self):
        super().run()
        if self.editable_mode:
            return
        for folder, pattern in DATA:
            target = Path(self.build_lib, "app", "_data", folder)
            target.mkdir(parents=True, exist_ok=True)
            for source in sorted(p for p in (HERE / folder).glob(pattern) if p.is_file()):
                self.copy_file(str(source), str(target / source.name))


setup(cmdclass={"build_py": BuildWithData})
