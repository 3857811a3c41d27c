#!/bin/sh
# valterm-login: the ForceCommand of an SSH login whose only program is the VAL-II SIMULATOR.
# Install: install -m 755 docs/valterm-login.sh /usr/local/bin/valterm-login
# (see docs/SERVING.md for the sshd_config Match block that uses it).
#
# - Refuses to start without a terminal: `ssh -T`, `ssh host CMD`, scp and sftp get a one-line
#   message and exit status 1 instead of a simulator hanging on a pipe.
# - exec: the simulator is the session's process, so when the client leaves, the hangup sshd
#   sends on closing the terminal ends it (ClientAliveInterval catches links that just die and
#   clients that stop reading: the simulator goes quiet for a terminal that does not answer).
# - Each login user has a workspace of their own, $HOME/valterm, private to them (umask 077).
# - A command given to ssh (ssh -t HOST CMD) is ignored, and said so before the simulator's
#   screen covers the terminal (VALTERM_NOTE_SECONDS, default 3, to read it).
# - Each login is recorded (every key with its time, every line shown; `valterm replay FILE`
#   plays it) in $HOME/valterm-records/<date>-<time>-<pid>.rec, outside the workspace;
#   VALTERM_RECORDS=DIR records elsewhere, VALTERM_RECORDS= (empty) not at all.

VALTERM="${VALTERM:-/opt/valterm/venv/bin/valterm}"

if [ ! -t 0 ] || [ ! -t 1 ]; then
    echo "valterm: this login runs the VAL-II SIMULATOR and needs a terminal: connect with 'ssh -t USER@HOST' (no -T, no command)." >&2
    exit 1
fi
if [ ! -x "$VALTERM" ]; then
    echo "valterm: $VALTERM is missing or not executable for $(id -un): ask the administrator (the venv must be readable by login users)." >&2
    exit 1
fi
# executable is not enough: the venv's interpreter or its packages may be unreadable for this
# user, and the simulator would die before its first screen; start it once to know
if ! "$VALTERM" --version >/dev/null 2>&1; then
    echo "valterm: $VALTERM does not start for $(id -un) ('$VALTERM --version' fails): ask the administrator (the venv must be readable by login users)." >&2
    exit 1
fi

if [ -n "$SSH_ORIGINAL_COMMAND" ]; then
    # said before the simulator starts, and left a moment to be read: the simulator's screen
    # covers the terminal at once (the note was seen only after it ended)
    echo "valterm: this login runs only the VAL-II SIMULATOR; the command '$SSH_ORIGINAL_COMMAND' is ignored." >&2
    echo "valterm: starting the simulator in ${VALTERM_NOTE_SECONDS:-3} seconds ..." >&2
    sleep "${VALTERM_NOTE_SECONDS:-3}"
fi

umask 077
RECORDS="${VALTERM_RECORDS-$HOME/valterm-records}"
if [ -n "$RECORDS" ] && mkdir -p "$RECORDS"; then
    set -- --record "$RECORDS/$(date +%Y-%m-%d-%H%M%S)-$$.rec"   # exec keeps the pid: a name of its own
else
    set --   # no record (turned off, or the folder cannot be made): the session runs all the same
fi
export TEXTUAL_COLOR_SYSTEM="${TEXTUAL_COLOR_SYSTEM:-256}"   # 256 colours travel well
export TEXTUAL_FPS="${TEXTUAL_FPS:-20}"                      # fewer frames on slow links
exec "$VALTERM" --workspace "$HOME/valterm" "$@"
