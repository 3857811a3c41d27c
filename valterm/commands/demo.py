"""``valterm demo``: the museum demo. The example session of Tables C-1..C-3 and CONV1
(valterm/data/DEMO.KEYS, read by ``valterm.core.files.demokeys``) played key by key in a loop,
with a caption line for the visitor; any key hands over, an idle minute starts it again.
``--kiosk`` also turns off the keys that would end it; ``--once`` plays it once and exits.
"""

from __future__ import annotations

import argparse
import sys


def register(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    parser = sub.add_parser("demo", help="replay the thesis's example session in a loop (museum mode)")
    parser.add_argument("--speed", type=float, default=1.0, help="faster (2) or slower (0.5) than the default pace")
    parser.add_argument("--once", action="store_true", help="play the script once, then exit")
    parser.add_argument("--kiosk", action="store_true",
                        help="unattended museum use: Ctrl-Q and the MAIN MENU's S (STOP) do not end it")
    parser.add_argument("--idle", type=float, default=60.0, metavar="SECONDS",
                        help="seconds without a key before the demo starts again (default 60)")
    parser.add_argument("--script", metavar="FILE", help="play this key script instead of the bundled DEMO.KEYS")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    if not args.speed > 0 or not args.idle > 0:
        print("valterm: demo: --speed and --idle must be positive", file=sys.stderr)
        return 2
    from valterm.ui.demo import run_demo

    return run_demo(speed=args.speed, once=args.once, kiosk=args.kiosk, idle=args.idle,
                    script=args.script, ascii=bool(getattr(args, "ascii", False)))
