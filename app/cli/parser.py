"""The `frost` command line: the window with no subcommand, one subcommand per other job.

Each subcommand has only the options that make sense for it; the shared ones come from
app.cli.shared_options.
"""

from __future__ import annotations

import argparse
import textwrap

from app.bench.results import shown
from app.cli import shared_options as options
from app.cli import values
from app.keys import help_lines
from sim import all_presets
from sim.io.files import one_line
from sim.screen import HEIGHT, WIDTH

PROG = "frost"
FIGURES = ("fern",)
BENCH_PRESET = "c-2"  # the renderer's benchmark grows Table 1's c-2 unless told otherwise


class Parser(argparse.ArgumentParser):
    """argparse whose errors are one line naming the problem (exit status 2), with no
    abbreviated options (each option is spelled one way), and which knows its
    subcommands' parsers by name. Its errors start `frost: error:`, but those of a
    command whose arguments another program parses (`own_prefix`): they start with the
    command's name, as that program's own errors do."""

    def __init__(self, own_prefix: bool = False, **kwargs):
        kwargs.setdefault("formatter_class", argparse.RawDescriptionHelpFormatter)
        super().__init__(allow_abbrev=False, **kwargs)
        self.commands: dict[str, Parser] = {}
        self.prefix = kwargs["prog"] if own_prefix else PROG

    def error(self, message: str):
        self.exit(2, f"{self.prefix}: error: {one_line(message)} (see {self.prog} --help)\n")

    def command(self, subs, name: str, summary: str, description: str = "",
                usage: str = "[options]", **kwargs) -> Parser:
        """A subcommand `name`: `summary` in the list of commands, `description` atop its help."""
        sub = subs.add_parser(name, prog=f"{self.prog} {name}", usage=f"%(prog)s {usage}",
                              help=summary, description=_para(description or summary), **kwargs)
        self.commands[name] = sub
        return sub


def _para(text: str) -> str:
    return textwrap.fill(text, 88)


def build_parser() -> Parser:
    root = _window()
    subs = root.add_subparsers(dest="command", title="commands (frost COMMAND --help for each)",
                               metavar="COMMAND")
    for add in (_render, _replay, _figure8, _figure, _maps, _bench, _serve, _web, _info):
        add(root, subs)
    return root


def _info(root: Parser, subs) -> None:
    root.command(subs, "info", "what a bug report needs: platform, Python, GLFW, the screen's "
                 "scale, the OpenGL contexts and the shader dialect",
                 "Print what a bug report needs, a line each: the platform, Python and the "
                 "libraries, the shader dialect, the headless OpenGL context, GLFW's platform, "
                 "the primary monitor's work area and content scale, and a window's OpenGL "
                 "context and framebuffer (or why there is no display).")


def parser_for(root: Parser, args: argparse.Namespace) -> Parser:
    """The parser of the command `args` came from (`root` for the window). A command with
    subcommands of its own keeps the one chosen under its own name (args.bench)."""
    if not args.command:
        return root
    parser = root.commands[args.command]
    if parser.commands:
        parser = parser.commands[getattr(args, args.command)]
    return parser


def _window() -> Parser:
    p = Parser(prog=PROG, usage="%(prog)s [options]           (the window)\n       "
                                "%(prog)s COMMAND [options]   (COMMAND below)", description=_para(
        f"Real-time window frost on a {WIDTH}x{HEIGHT} phone screen. With no COMMAND it opens the "
        "window: click (or drag) to plant seed crystals, drag with the right button to melt "
        "the ice (a warm finger). Each session with a touch, melt or change is saved "
        "(--session-dir) and frost replay "
        "plays it again bit for bit. With no display it grows the scripted demo (or the "
        "frosted window) offscreen and writes PNG files to frost-out/ instead."),
        epilog="keys in the window:\n  " + "\n  ".join(help_lines()))
    options.add_preset(p)
    options.add_seed(p)
    options.add_touch(p, options.PLANT, "none")
    options.add_window(p)
    options.add_clock_start(p)
    options.add_background(p)
    options.add_ticks(p, options.DEFAULT_TICKS,
                      "with no display: how long the PNG render done instead grows")
    options.add_weather(p, "read at the start and every --weather-every minutes; T and Y "
                           "then change nothing")
    options.add_weather_every(p)
    options.add_overrides(p)
    # What the no-display fallback (frost render's code) reads and the window has no options for.
    p.set_defaults(replay=None, melt=[], melt_path=[], out=None, clock=None)
    return p


def _render(root: Parser, subs) -> None:
    p = root.command(subs, "render", "grow the frost offscreen (no display needed) and write PNGs",
                     "Grow the frost offscreen (EGL, no display needed) and write a PNG. With no "
                     "--touch (and no window mode, which frosts from the frame untouched) it runs "
                     "the scripted demo (three touches over the run) and writes a PNG after each "
                     "stage into the folder of --out (default frost-out/), new names each run.")
    options.add_preset(p)
    options.add_seed(p)
    options.add_touch(p, options.PLANT, "the scripted demo; none in window mode")
    options.add_ticks(p, options.DEFAULT_TICKS, "how long to grow")
    options.add_out(p, demo=True)
    options.add_melts(p)
    options.add_background(p)
    options.add_clock(p)
    options.add_weather(p, "read once, before tick 0 (at most 5 s)")
    options.add_overrides(p)


def _replay(root: Parser, subs) -> None:
    p = root.command(subs, "replay", "play a recorded session again, windowed or to a PNG",
                     "Play a recorded session (sessions/*.json) again bit for bit: its seed, "
                     "parameters, touches, melts and changes at their ticks. Windowed when a "
                     "display exists; headless (a PNG after --ticks) with --headless, --out or "
                     "--ticks, or with no display.", "FILE.json [options]")
    p.add_argument("replay", metavar="FILE.json", help="the session file")
    options.add_params(p, options.REPLAY_SET, overrides=False)
    options.add_background(p)
    g = p.add_argument_group("headless")
    g.add_argument("--headless", action="store_true", help="render offscreen, no window (default off)")
    options.add_ticks(g, None, "how far to replay")
    options.add_out(g)
    options.add_window(p.add_argument_group("window"))


def _figure8(root: Parser, subs) -> None:
    p = root.command(subs, "figure8", "the paper's Fig. 8: the nine Table 1 presets on one sheet",
                     "Render the nine Table 1 presets (a-1 ... c-3) from one touch into a 3x3 "
                     "sheet (Fig. 8), print each preset's numbers, and exit.", "FILE.png [options]")
    p.add_argument("out", metavar="FILE.png", help="the sheet to write (.png, or .jpg/.jpeg for JPEG)")
    options.add_params(p, options.FIGURE8_SET)
    options.add_seed(p)
    options.add_ticks(p, options.DEFAULT_TICKS, "how long each preset grows")
    options.add_touch(p, "the one touch", "the centre, 380,640")
    options.add_background(p)
    options.add_overrides(p, looks=())  # on top of each of Table 1's presets


def _figure(root: Parser, subs) -> None:
    p = root.command(subs, "figure", "a labelled sheet of growth over time (fern)",
                     "Render a labelled sheet of fern growth (ticks 25 ... 750, one touch and three "
                     "touches) with the chosen parameters, and exit.", "KIND FILE.png [options]")
    p.add_argument("kind", choices=FIGURES, metavar="KIND", help=f"which figure: {', '.join(FIGURES)}")
    p.add_argument("out", metavar="FILE.png", help="the sheet to write (.png, or .jpg/.jpeg for JPEG)")
    options.add_preset(p)
    options.add_seed(p)
    options.add_background(p)
    options.add_overrides(p)


def _maps(root: Parser, subs) -> None:
    p = root.command(subs, "maps", "height, normal, alpha and growth maps of grown frost for game "
                     "engines", "Grow the frost (no display needed) and write to DIR, for game "
                     "engines: height.png (16-bit), normal.png, alpha.png, growth.png (16-bit: "
                     "when each pixel froze, so an engine replays the freeze with one threshold), "
                     "preview.png and maps.json (what each file and channel holds). With no "
                     "--touch it grows the scripted demo's three touches (window mode: none).",
                     "DIR [options]")
    p.add_argument("out_dir", metavar="DIR", help="the folder to write the maps into")
    options.add_preset(p)
    options.add_seed(p)
    lo, hi = values.MAPS_SIDE
    p.add_argument("--size", type=values.size, default=(WIDTH, HEIGHT), metavar="WxH",
                   help=f"the maps' size in px, each side {lo} ... {hi} (default {WIDTH}x{HEIGHT}, "
                        "the phone screen)")
    p.add_argument("--tile", action="store_true",
                   help="seamless in both directions: the frost wraps around every edge (window "
                        "mode grows from pane sites only; default off)")
    p.add_argument("--normal-y", choices=("up", "down"), default="up", metavar="up|down",
                   help="normal.png's green channel: up = OpenGL (Godot, Unity, Blender, glTF), "
                        "down = DirectX (Unreal) (default up)")
    options.add_touch(p, options.PLANT, "the scripted demo", kind=values.point,
                      where="on the maps (0 <= X < W, 0 <= Y < H of --size)")
    options.add_ticks(p, options.DEFAULT_TICKS, "how long to grow")
    options.add_overrides(p)


def _serve(root: Parser, subs) -> None:
    from app.backdrops import BACKDROPS
    from app.serve import DEFAULT_PORT, MAX_PAGES

    p = root.command(subs, "serve", "the frost for phones: a page that a browser opens, over HTTP "
                     "and WebSockets", "Run the simulation and serve it to phones and browsers "
                     f"(docs/phone.md): every page (at most {MAX_PAGES}) shows the same pane and "
                     "every touch grows it; the session is saved as the window saves it. Binds "
                     "127.0.0.1 unless told; any other --host prints a URL with a token (kept "
                     "across runs) and its QR code, refuses requests without it, and serves "
                     "HTTPS too on a second port, with a certificate of a local authority "
                     "frost keeps, which a phone can trust.")
    p.add_argument("--host", default="127.0.0.1", metavar="H",
                   help="address to listen on, e.g. 0.0.0.0 for a phone on the same network "
                        "(default 127.0.0.1: this machine only)")
    p.add_argument("--port", type=lambda text: values.whole(text, 65535), default=DEFAULT_PORT,
                   metavar="P", help=f"TCP port, 0 for any free one (default {DEFAULT_PORT})")
    p.add_argument("--https-port", type=lambda text: values.whole(text, 65535), default=None,
                   metavar="P", help="TCP port of HTTPS and WSS (served with any --host but "
                        "127.0.0.1, or when asked), 0 for any free one (default: --port + 1; "
                        "with --port 0 a free one)")
    p.add_argument("--cert", metavar="FILE", default=None,
                   help="serve HTTPS with this certificate (PEM; e.g. mkcert's or a real "
                        "domain's) instead of one from frost's own local authority; needs --key")
    p.add_argument("--key", metavar="FILE", default=None, help="the private key of --cert (PEM)")
    p.add_argument("--no-https", action="store_true",
                   help="serve plain HTTP alone, even with --host 0.0.0.0 (default off)")
    p.add_argument("--new-token", action="store_true",
                   help="replace the token kept across runs (pages opened with the old one, "
                        "installed ones too, are refused from now on; default off)")
    options.add_preset(p)
    options.add_seed(p)
    options.add_touch(p, options.PLANT, "none")
    p.add_argument("--background", choices=list(BACKDROPS), default="dusk", metavar="NAME",
                   help=f"the view behind the glass: {', '.join(BACKDROPS)} (default dusk)")
    p.add_argument("--window", action="store_true",
                   help="also open the desktop window on the same frost (it then writes the "
                        "session, as it does alone; default off)")
    options.add_window(p)
    options.add_clock_start(p)
    options.add_weather(p, "read at the start and every --weather-every minutes, for every page")
    options.add_weather_every(p)
    options.add_overrides(p)


def _web(root: Parser, subs) -> None:
    p = root.command(subs, "web", "the phone page as a static site, for any web host (no "
                     "computer needed)", "Write the phone page into DIR as a static site "
                     "(docs/phone.md, Without a computer): any static web server serves it as "
                     "it is, at its root or under a sub-path; opened there, the page grows its "
                     "own frost at once, installs to the home screen and opens offline. A site "
                     "built again into DIR replaces the old one whole.", "DIR [options]")
    p.add_argument("site_dir", metavar="DIR", help="the folder to write the site into (new, "
                   "empty, or a site frost web wrote before)")
    options.add_weather_apis(p, ", which the page asks itself")


def _bench(root: Parser, subs) -> None:
    p = root.command(subs, "bench", "benchmarks: the simulation (sim) or the renderer (render); "
                     "the page's and the server's are a checkout's: python -m bench page|serve",
                     usage="WHAT [options]")
    kinds = p.add_subparsers(dest="bench", title="benchmarks", metavar="WHAT", required=True)
    # Never parsed here (app.cli.commands hands its arguments to app.bench.simulation, as argparse
    # cannot pass on options it does not know); listed so that frost bench --help names it.
    p.command(kinds, "sim", "the simulation's benchmark: every argument, --help too, goes to "
              "python -m app.bench.simulation", usage="[ARGS ...]", add_help=False,
              own_prefix=True)
    _bench_render(p.command(kinds, "render", "the renderer's benchmark: frame, geometry and "
                            f"upload times at about half the screen frosted (headless, {WIDTH}x{HEIGHT})"))


def _bench_render(p: Parser) -> None:
    p.add_argument("--preset", choices=list(all_presets()), metavar="NAME",
                   help=f"parameter set to grow (default {BENCH_PRESET})")
    options.add_params(p, "grown and rendered (in each look) instead of a preset")
    p.set_defaults(default_preset=BENCH_PRESET)
    options.add_seed(p)
    p.add_argument("--frames", type=values.count, default=60, metavar="N",
                   help="frames to time, frames (default 60)")
    p.add_argument("--cover", type=values.fraction, default=0.5, metavar="F",
                   help="fraction of the screen to frost before timing frames (default 0.5)")
    p.add_argument("--max-ticks", type=values.whole, default=600, metavar="N",
                   help="most ticks to grow toward --cover, ticks (default 600)")
    options.add_background(p)
    p.add_argument("--record", action="store_true",
                   help=f"also keep the figures, dated, at the top of {shown('render')} (default off)")
