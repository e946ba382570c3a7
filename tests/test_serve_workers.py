"""Work drawn off the loop (app/serve/workers.py): on the loop's executor while the loop
runs, its result handed back on the loop's thread; here, at once, otherwise."""

from __future__ import annotations

import asyncio
import threading

from app.serve.workers import Workers


def test_without_a_running_loop_the_work_is_done_here_at_once():
    workers, seen = Workers(), []
    workers.loop = asyncio.new_event_loop()  # (set, but not running: the end's last pump)
    try:
        workers.run(lambda n: (n * n, threading.get_ident()), 7, seen.append)
    finally:
        workers.loop.close()
    assert seen == [(49, threading.get_ident())]


def test_while_the_loop_runs_the_work_is_on_a_worker_and_its_result_back_on_the_loop():
    async def main():
        workers, loop = Workers(), asyncio.get_running_loop()
        workers.loop = loop
        done: asyncio.Future = loop.create_future()
        workers.run(lambda n: (n + 1, threading.get_ident()), 41,
                    lambda result: done.set_result((result, threading.get_ident())))
        return await asyncio.wait_for(done, 30)

    (value, worker), back = asyncio.run(main())
    here = threading.get_ident()
    assert value == 42 and worker != here and back == here
