"""``valterm serve --web``: the app in a web browser, one simulator process per browser tab
(textual-serve, the optional ``web`` extra).

The page textual-serve hands out is replaced by valterm/data/web/app_index.html: it asks
nothing from the internet (the font and the scripts come from this server) and every address
in it starts with the public URL, so it works from other machines and behind a TLS proxy
(``https://`` gives ``wss://`` for the websocket). Without ``--public-url`` the public URL is
``http://HOST:PORT`` for a named host; on a wildcard host (0.0.0.0, ::) each page points back
at the address its browser used (the Host header), never at 0.0.0.0.
"""

from __future__ import annotations

import argparse
import re
import shlex
import sys
from typing import Any
from urllib.parse import urlsplit

from valterm.commands.robots import robot_from
from valterm.core.errors import RefusedValue

WILDCARD_HOSTS = ("0.0.0.0", "::", "[::]", "")
# what a Host header may hold (a name or an address and a port): anything else is refused
_HOST_HEADER = re.compile(r"[A-Za-z0-9.\-]+(:[0-9]{1,5})?|\[[0-9A-Fa-f:.]+\](:[0-9]{1,5})?")


def register(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    serve = sub.add_parser("serve", help="serve the app to web browsers (needs valterm[web])",
                           description="Serve the VAL-II SIMULATOR to web browsers: each tab runs its own "
                                       "simulator on the workspace. See docs/SERVING.md.")
    serve.add_argument("--web", action="store_true", help="serve over HTTP with textual-serve")
    serve.add_argument("--host", default="localhost", help="the address to listen on (default localhost; 0.0.0.0 for all)")
    serve.add_argument("--port", type=int, default=8000, help="the port (default 8000)")
    serve.add_argument("--public-url", metavar="URL",
                       help="the address browsers use, e.g. https://valterm.example.org behind a TLS proxy "
                            "(default http://HOST:PORT; on 0.0.0.0 the address each browser used)")
    serve.set_defaults(func=run_serve)


def public_url_of(text: str) -> str:
    """``--public-url`` checked: http(s)://host[:port][/path], without a trailing slash."""
    parts = urlsplit(text.strip())
    if parts.scheme not in ("http", "https") or not parts.netloc or parts.query or parts.fragment:
        raise RefusedValue(f"--public-url {text!r} is not an http:// or https:// address like https://valterm.example.org")
    return f"{parts.scheme}://{parts.netloc}{parts.path.rstrip('/')}"


def default_public_url(host: str, port: int) -> str | None:
    """The public URL for a named host; None on a wildcard host (derived per request)."""
    if host.strip() in WILDCARD_HOSTS:
        return None
    name = f"[{host}]" if ":" in host and not host.startswith("[") else host
    return f"http://{name}" if port == 80 else f"http://{name}:{port}"


def app_command(args: argparse.Namespace) -> str:
    """The command textual-serve starts for each browser tab."""
    command = [sys.executable, "-m", "valterm"]
    if getattr(args, "workspace", None):
        command += ["--workspace", args.workspace]
    if getattr(args, "setup", None):
        command += ["--setup", args.setup]
    if getattr(args, "ascii", False):
        command.append("--ascii")
    if robot_from(args):  # valterm --robot PUMA560 serve: every tab's app on the 560
        command += ["--robot", str(robot_from(args))]
    return shlex.join(command)


def make_server(command: str, host: str, port: int, public_url: str | None) -> Any:
    """A textual-serve server with valterm's page and favicon (textual_serve imported here)."""
    from aiohttp import web
    from textual_serve.server import Server, to_int

    from valterm.core import resources

    web_folder = resources.data_path("web")

    class ValtermServer(Server):
        def __init__(self) -> None:
            super().__init__(command, host=host, port=port, title="VAL-II SIMULATOR",
                             public_url=public_url or "http://localhost", templates_path=web_folder)
            self.fixed_url = public_url

        async def _make_app(self) -> web.Application:
            app = await super()._make_app()
            app.router.add_get("/favicon.ico", self.handle_favicon)
            return app

        async def handle_favicon(self, request: web.Request) -> web.StreamResponse:
            return web.FileResponse(web_folder / "favicon.ico", headers={"Content-Type": "image/x-icon"})

        def base_url(self, request: web.Request) -> str:
            """The public URL, or (wildcard host) the address this browser used."""
            if self.fixed_url:
                return str(self.fixed_url)
            proto = request.headers.get("X-Forwarded-Proto", request.scheme).split(",")[0].strip().lower()
            where = request.headers.get("X-Forwarded-Host", request.host).split(",")[0].strip()
            if proto not in ("http", "https") or not _HOST_HEADER.fullmatch(where):
                raise web.HTTPBadRequest(text="valterm: the Host header is not a host name or address")
            return f"{proto}://{where}"

        async def handle_index(self, request: web.Request) -> web.Response:
            import aiohttp_jinja2

            base = self.base_url(request)
            router = request.app.router
            static = f"{base}{router['static'].url_for(filename='/')}".rstrip("/") + "/"
            websocket = f"{base}{router['websocket'].url_for()}"
            websocket = ("wss:" if base.startswith("https:") else "ws:") + websocket.split(":", 1)[1]
            context = {
                "font_size": to_int(request.query.get("fontsize", "16"), 16),
                "app_websocket_url": websocket,
                "favicon_url": f"{base}/favicon.ico",
                "config": {"static": {"url": static}},
                "application": {"name": self.title},
            }
            return aiohttp_jinja2.render_template("app_index.html", request, context)

        async def on_startup(self, app: web.Application) -> None:
            where = self.fixed_url or f"the address each browser uses (listening on all addresses, port {port})"
            self.console.print(f"valterm: serving the VAL-II SIMULATOR on {where}")
            self.console.print("valterm: Ctrl+C stops the server")

    return ValtermServer()


def run_serve(args: argparse.Namespace) -> int:
    if not args.web:
        print("valterm: serve: say --web to serve the app over HTTP (valterm serve --web --port 8000)", file=sys.stderr)
        return 2
    if not 0 < args.port < 65536:
        print(f"valterm: serve: --port {args.port} is not a port (1 to 65535)", file=sys.stderr)
        return 2
    try:
        public_url = public_url_of(args.public_url) if args.public_url else default_public_url(args.host, args.port)
    except RefusedValue as error:
        print(f"valterm: serve: {error}", file=sys.stderr)
        return 2
    try:
        import textual_serve  # noqa: F401
    except ImportError:
        print("valterm: serve --web needs textual-serve: pip install 'valterm[web]'", file=sys.stderr)
        return 1
    if public_url is None:
        print("valterm: serve: listening on all addresses; each page points back at the address its browser "
              "used. Behind a TLS proxy or load balancer give --public-url https://NAME.", file=sys.stderr)
    try:
        make_server(app_command(args), args.host, args.port, public_url).serve()
    except OSError as error:
        print(f"valterm: serve: cannot listen on {args.host}:{args.port}: {error.strerror or error}", file=sys.stderr)
        return 1
    return 0
