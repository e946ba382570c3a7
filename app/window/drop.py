"""An image file dropped on the window becomes the backdrop, as a photo sent from a page
does (app/photos.py): checked and re-encoded on a worker thread (a phone photo takes a
few hundred ms to decode, the frame loop does not wait), kept in the session folder's
backdrops/, then shown through the simulation thread so that the session records it."""

from __future__ import annotations

import logging
import threading
from pathlib import Path

from app.photos import PhotoError, keep, read_file

log = logging.getLogger(__name__)


class PhotoDrop:
    """GLFW's drop callback for one window: `thread` (a SimThread) records and shows the
    photo; `store` is the folder photos are kept in."""

    def __init__(self, thread, store: Path):
        self.thread, self.store = thread, Path(store)
        self.worker: threading.Thread | None = None

    def on_drop(self, _window, paths) -> None:
        paths = list(paths)
        if not paths:
            return
        if self.worker is not None and self.worker.is_alive():
            self.thread.notify(logging.WARNING, "a dropped photo is still being read: drop "
                               "again when it shows")
            return
        if len(paths) > 1:
            self.thread.notify(logging.INFO, f"{len(paths)} files dropped: the first taken")
        self.worker = threading.Thread(target=self._take, args=(Path(paths[0]),),
                                       name="frost-drop", daemon=True)
        self.worker.start()

    def _take(self, path: Path) -> None:
        try:
            name = keep(read_file(path), self.store)
        except PhotoError as err:
            self.thread.notify(logging.WARNING, f"dropped {path.name}: refused: {err}")
            return
        except OSError as err:
            self.thread.notify(logging.WARNING, f"dropped {path.name}: cannot keep it in "
                               f"{self.store}: {err.strerror or err}")
            return
        except Exception as err:  # noqa: BLE001 (a worker's failure is said, never silent)
            log.exception("dropped %s", path)
            self.thread.notify(logging.WARNING, f"dropped {path.name}: refused: {err}")
            return
        self.thread.show_backdrop(name)
        self.thread.notify(logging.INFO, f"background: the photo {path.name} ({name})")
