"""The one event pump: every screen that plays what the core yields plays it here.

A ``Player`` takes the core's event stream (a typed command, EXECUTE, a pendant jog, a
MOVE of D_DEFINE) and works through it in ticks on its host's timers:

- poses are paced by elapsed time on the injectable clock (``core.render.clock``): a
  motion takes the real PUMA's time for it (``PoseEvent.seconds``, the cycle-time estimate)
  times the playback ``factor``; DELAY waits its seconds times the factor on the same
  clock; with ``rate`` infinite both happen at once (tests); ``rate`` paces the poses of a
  motion that announces no time;
- while a motion is paced the picture moves on at ``DRAW_RATE`` frames a second on the
  stream's one frame clock, a pose falling due between two frames drawn at the next, and at
  most one picture a frame (a motion's end and the next one's start wait for the frame
  after the last picture; issue 40): the screen redraws and the app draws
  the robot at ``drawn()``, each joint turned part of the way (the shortest turn) from the
  pose before the one due to it. Only the picture: the simulator stands at the motion's own
  pose, and the verdicts and lines are those of its poses (the same as ``valterm run``);
- whatever the program does (``10 GOTO 10`` has no motion and no DELAY) a tick works at
  most ``budget`` seconds of the app's own CPU time and ``TICK_LIMIT`` of real time, then
  hands control back to Textual, so the screen updates and CTRL-C is seen at the next tick
  (CPU time: on a loaded machine, the time other processes take must not shrink each
  tick's work, or ever more ticks, each with its redraw, would do ever less);
- every other event becomes transcript lines through the core's one renderer
  (``core.text.transcript``), posted once a tick (at most ``TRANSCRIPT_LINES`` a tick: a
  runaway TYPE loop cannot flood memory); a screen's own events (HELP, a monitor command,
  a finding) are posted as themselves, in their place among the lines;
- PAUSE stops the pump until ``resume()``; ``abort()`` asks the source to stop after its
  step (a running program: the core then says ABORTED) or closes it where it stands.

The player posts what the stream does as messages (``ui.messages``: TranscriptLines,
SceneShown, PictureMoved, RunEvent, RunPaused, RunEnded) through the ``post`` it is given
(the app's: to the screen that asked, or the one on top); the screens draw, and the player
never touches a widget nor knows a screen. It keeps no history: ``Transcript`` is the
capped record a screen keeps of what it showed.
"""

from __future__ import annotations

import asyncio
import math
import time
from collections import deque
from collections.abc import Callable, Generator, Iterable, Iterator, Sequence

from textual.message import Message as TextualMessage
from textual.message_pump import MessagePump

from valterm.core.events import (
    Collision,
    Contact,
    Delay,
    Event,
    Grasp,
    Hand,
    Help,
    Message,
    Monitor,
    Motion,
    Near,
    Pause,
    PoseEvent,
    Release,
)
from valterm.core.render.clock import DEFAULT_RATE, MotionPlayer
from valterm.core.render.legend import TRACE_POINTS
from valterm.core.text.transcript import event_lines
from valterm.ui.errors import problem_text
from valterm.ui.messages import (
    PictureMoved,
    RunEnded,
    RunEvent,
    RunPaused,
    SceneShown,
    TranscriptLines,
)

Post = Callable[[TextualMessage], object]  # where the player's messages go (the app routes them)

TICK_BUDGET = 0.005  # seconds of the app's CPU a tick, then Textual gets the loop back
TICK_LIMIT = 0.025  # ... or this much real time, however little CPU it had (a file's fsync)
YIELD = 0.001  # seconds the pump sleeps between busy ticks (keys and redraws run then)
# pictures a second while a motion is paced (the real PUMA's poses come 10-15 a second at
# SPEED 100): its poses and, between them, each joint turned part of the way to the next,
# drawn only. 30 is smooth to the eye and what a terminal over SSH takes; each frame costs
# the app's CPU (issue 40: a running session at a tenth of a core)
DRAW_RATE = 30.0
TRANSCRIPT_LINES = 2000  # lines a screen keeps of its transcript (and the most handed a tick)
# the on-screen log keeps fewer: a line there is a few Textual strips (about 5 KB with their
# caches, 8 KB of resident memory), so 2000 of them took 20 minutes of a looping program and
# 17 MiB to fill; these fill in minutes and hold about 2 MiB
LOG_LINES = 500
LOG_CACHE = 200  # rendered log lines kept (Textual's 1024 is for any widget; a screen shows < 100)
# playback factors: the animation takes the real robot's time times this (x0.25 is 4x faster)
FACTORS = (0.25, 0.5, 1.0, 2.0, 4.0, 8.0)

# events after which the picture changes although no pose came
_SCENE_EVENTS = (PoseEvent, Motion, Hand, Grasp, Release)
# events shown while a motion is paced (between its poses); anything else ends the motion
_DURING_MOTION = (Near, Collision, Message)
# a screen's own events: posted as themselves (RunEvent), the screen takes them or shows their lines
_OWN_EVENTS = (Help, Monitor, Contact)


class Transcript(deque[str]):
    """The lines a screen showed, the last ``TRANSCRIPT_LINES`` of them (memory stays flat)."""

    def __init__(self, lines: Iterable[str] = (), maxlen: int = TRANSCRIPT_LINES) -> None:
        super().__init__(lines, maxlen=maxlen)


class Player:
    """Plays one event stream at a time on ``host``'s timers (see the module's docstring)."""

    def __init__(self, host: MessagePump, *, clock: Callable[[], float] = time.monotonic,
                 rate: float = DEFAULT_RATE, budget: float = TICK_BUDGET,
                 real_time: Callable[[], float] = time.perf_counter,
                 cpu_time: Callable[[], float] = time.thread_time) -> None:
        self.host = host
        self.clock = clock
        # a tick's own clocks (tests give fakes): the real time it took, the CPU it had
        self.real_time, self.cpu_time = real_time, cpu_time
        self.rate = rate
        self.budget = budget
        self.factor = 1.0  # the playback factor (FACTORS): real time x factor
        self.goal: tuple[float, ...] | None = None  # the target of the motion under way (or last)
        self.collided: set[str] = set()  # parts and links found colliding in this stream
        self.ticks = 0  # ticks worked so far (tests count them)
        self.abort_tick = -1  # the tick count when CTRL-C came, and when the stream ended
        self.end_tick = -1
        self._source: Iterator[Event] | None = None
        self._post: Post | None = None
        self._stop_source: Callable[[], bool] | None = None
        self._motion: MotionPlayer[PoseEvent] | None = None
        self._after_motion: list[Event] = []
        self._resume_at: float | None = None
        self._paused = False
        self._aborting = False
        self._lines: deque[str] = deque(maxlen=TRANSCRIPT_LINES)
        self._scene_changed = False
        self._picture_changed = False  # only the in-between picture moved (PictureMoved)
        self._last_pause: Pause | None = None  # to post after the lines
        self._ended: bool | None = None  # the stream ended (aborted?): to post
        self._timer: asyncio.TimerHandle | None = None
        # drawing only: the pose before the one shown and that pose, the picture in between
        self._last_pose: tuple[float, ...] | None = None  # the last pose the robot was seen at
        # the tool path's poses: every pose the stream went through, not only those a frame
        # showed (a slow terminal draws fewer; the path must not turn into chords)
        self._passed: deque[tuple[float, ...]] = deque(maxlen=TRACE_POINTS)
        self._segment: tuple[tuple[float, ...], tuple[float, ...]] | None = None
        self._between: tuple[float, ...] | None = None
        self._tick_start = self._tick_cpu = 0.0  # real_time() and cpu_time() as the tick began
        # the stream's frame clock (clock() at its start) and the frame of its last picture
        self._frame_origin = 0.0
        self._last_frame: int | None = None

    # -- state -----------------------------------------------------------------------
    @property
    def playing(self) -> bool:
        """A stream is under way (also while paused)."""
        return self._source is not None

    @property
    def paused(self) -> bool:
        return self._paused

    def drawn(self, joints: Sequence[float]) -> tuple[float, ...] | None:
        """The joints to draw the robot at instead of ``joints`` (the simulator's): while a
        motion is paced, a pose between the motion's pose shown and the one before it, as far
        along as the clock is towards the next; None: draw ``joints``. Drawn only: the
        simulator, the verdicts and the transcript are the motion's own poses'."""
        if self._motion is None:
            self.rest_at(joints)
            return None
        if self._segment is None or tuple(joints) != self._segment[1]:
            return None  # the robot is not where the motion put it: draw it as it is
        return self._between

    def passed_poses(self) -> list[tuple[float, ...]]:
        """The motions' poses the stream went through since the last call, in order (the
        tool path draws each, as ``valterm render --trace`` does)."""
        passed = list(self._passed)
        self._passed.clear()
        return passed

    def rest_at(self, joints: Sequence[float]) -> None:
        """The robot is at ``joints`` with no motion playing: the next motion's pictures
        start there (also when it was moved without a pose or a redraw)."""
        if self._motion is None:
            self._last_pose = tuple(joints)

    @property
    def drawing(self) -> bool:
        """A motion is being drawn pose by pose (keys typed now wait: ``ui.keyqueue``)."""
        return self._motion is not None and not self._paused

    # -- control ---------------------------------------------------------------------
    def play(self, events: Iterable[Event], post: Post,
             stop: Callable[[], bool] | None = None) -> None:
        """Play ``events``, posting what they do through ``post``; a motion still playing
        first jumps to its end.

        ``stop()`` is how CTRL-C reaches the source: it returns True when the source will
        end by itself after its current step (a running program), False to close it.
        """
        if self.playing:  # a running program is stopped first: a loop has no end to skip to
            if self._stop_source is not None and self._stop_source():
                self._aborting = True
            self.skip_to_end()
        self._source, self._post, self._stop_source = iter(events), post, stop
        self.collided = set()
        self._frame_origin, self._last_frame = self.clock(), None
        self._paused = self._aborting = False
        self._tick()  # the first events (and a refusal) at once

    def resume(self) -> None:
        """After PAUSE: go on (PROCEED was typed)."""
        if self._paused:
            self._paused = False
            self._schedule(0.0)

    def abort(self) -> None:
        """CTRL-C: the program stops after its step; anything else stops where it stands."""
        if not self.playing or self._aborting:
            return
        self._aborting = True
        self.abort_tick = self.ticks
        self._paused = False
        self._resume_at = None
        if self._stop_source is None or not self._stop_source():
            self._end(aborted=True)
            return
        self._schedule(0.0)  # the next tick sees the program's ABORTED

    def close(self) -> None:
        """The app is closing: end the stream where it stands, telling no one."""
        self._post = None
        if self.playing:
            self._end(aborted=True)

    def skip_to_end(self) -> None:
        """Run the stream to its end now, no pacing, no DELAY (tests, an impatient user).

        A paused stream is left paused: PAUSE waits for the user.
        """
        while self.playing and not self._paused:
            self._resume_at = None
            self._guarded(math.inf, pace=False)
            self._flush()
        if self.playing:  # paused: a new stream replaces it
            self._end(aborted=True)

    # -- the tick --------------------------------------------------------------------
    def _tick(self) -> None:
        self._timer = None
        if not self.playing:
            return
        self.ticks += 1
        self._tick_start, self._tick_cpu = self.real_time(), self.cpu_time()
        pace = not math.isinf(self.rate)
        wait = self._guarded(self._tick_start + self.budget, pace=pace)
        held = self._flush(pace)
        if held is not None:  # the picture waits for the next frame
            wait = held if wait is None else min(wait, held)
        if wait is not None and self.playing and not self._paused:
            self._schedule(wait)

    def _schedule(self, delay: float) -> None:
        """The next tick in ``delay`` seconds (at least YIELD: the loop breathes), on the
        event loop itself: a Textual timer is a task, a partial and two signature
        inspections a tick, about as much as the tick's own work (issue 40)."""
        if self._timer is not None:
            self._timer.cancel()
        self._timer = asyncio.get_running_loop().call_later(max(YIELD, delay), self._timed_tick)

    def _timed_tick(self) -> None:
        """A tick from the loop: a bug in it goes to the app as a Textual timer's would."""
        try:
            self._tick()
        except Exception as error:
            self.host.app._handle_exception(error)

    def _guarded(self, deadline: float, pace: bool) -> float | None:
        """``_work``, with a refusal or a bug of the source shown as a line that ends the stream."""
        try:
            return self._work(deadline, pace)
        except Exception as error:
            self._lines.append(problem_text(error))
            self._end(aborted=self._aborting)
            return None

    def _work(self, deadline: float, pace: bool) -> float | None:
        """Pull events until the budget is spent, a pose or DELAY must wait, PAUSE or the end.

        Returns the seconds until the next tick is due, or None when none is. A tick takes at
        least one event before it looks at the clock: one preempted before its first (a loaded
        machine) would do nothing, and tick after tick might.
        """
        took = False
        while self.playing and not self._paused:
            if self._motion is not None:
                wait = self._motion_step(pace)
                if wait is not None:
                    return wait
                continue
            if self._resume_at is not None:
                now = self.clock()
                if now < self._resume_at and not self._aborting:
                    return min(self._resume_at - now, 0.1)  # a fresh look at the clock
                self._resume_at = None
            if took and self.real_time() > deadline:
                later = self._more_time()
                if later is None:
                    return 0.0
                deadline = later
            try:
                event = next(self._source)  # type: ignore[arg-type]
            except StopIteration:
                self._end(aborted=self._aborting)
                return None
            self._take(event, pace)
            took = True
        return None

    def _more_time(self) -> float | None:
        """The tick's real time is up: a later deadline when it has had less than ``budget`` of
        CPU (other processes had the rest) and is within ``TICK_LIMIT``; None when it is over.
        Looked at only then: the CPU clock is a system call, the real one is not."""
        now = self.real_time()
        left = self.budget - (self.cpu_time() - self._tick_cpu)
        if left <= 0.0 or now - self._tick_start >= TICK_LIMIT:
            return None
        return now + left

    def _take(self, event: Event, pace: bool) -> None:
        if isinstance(event, _SCENE_EVENTS):
            self._scene_changed = True
        if isinstance(event, PoseEvent):
            self.goal = event.goal or None
            if pace and not self._aborting:
                self._motion = self._paced(event)
            else:
                self._last_pose = event.joints
                self._passed.append(event.joints)
            return
        if isinstance(event, Delay):
            if pace and not self._aborting:
                self._resume_at = self.clock() + float(event.seconds) * self.factor
            return
        self._show(event)
        if isinstance(event, Pause):
            self._paused, self._last_pause = True, event

    def _paced(self, first: PoseEvent) -> MotionPlayer[PoseEvent]:
        """The motion's poses on the clock: it ends ``seconds x factor`` from now."""
        seconds = float(first.seconds) * self.factor
        if seconds <= 0 or first.steps <= 0 or math.isinf(self.rate):
            return MotionPlayer(self._poses(first), self.rate, clock=self.clock)
        # pose i (from 0) is due at i / rate; the motion is over when pose `steps` would be
        # due, `seconds` from now (what follows it is pulled then)
        return MotionPlayer(self._poses(first), first.steps / seconds, clock=self.clock)

    def set_factor(self, factor: float) -> float:
        """A new playback factor (from the next motion or DELAY on); returns it."""
        if not (factor > 0 and math.isfinite(factor)):
            raise ValueError("the playback factor must be a positive number")
        self.factor = float(factor)
        return self.factor

    def change_factor(self, steps: int) -> float:
        """Move ``steps`` along FACTORS (+1: slower, each motion takes twice the time)."""
        nearest = min(range(len(FACTORS)), key=lambda i: abs(math.log(FACTORS[i] / self.factor)))
        return self.set_factor(FACTORS[max(0, min(len(FACTORS) - 1, nearest + steps))])

    def _show(self, event: Event) -> None:
        if isinstance(event, Collision):
            self.collided.update((event.a, event.b))
        if isinstance(event, _OWN_EVENTS) and self._post is not None:
            self._post_lines()  # the lines before it first: the screen sees them in order
            self._post(RunEvent(event, event_lines(event)))
            return
        self._lines.extend(event_lines(event))

    def _poses(self, first: PoseEvent) -> Iterator[PoseEvent]:
        """The poses of one motion, pulled from the stream as the clock wants them; findings
        between poses are shown as they come, the first other event is kept for after."""
        self._arrive(first)
        yield first
        for event in self._source or ():
            if isinstance(event, PoseEvent):
                self._arrive(event)
                yield event
            elif isinstance(event, _DURING_MOTION):
                self._show(event)
            else:
                self._after_motion.append(event)
                return

    def _arrive(self, pose: PoseEvent) -> None:
        """A pose pulled from the stream: the simulator is there now (the next to be shown)."""
        before, self._last_pose = self._last_pose, pose.joints
        self._passed.append(pose.joints)
        self._segment = None if before is None else (before, pose.joints)

    def _in_between(self, motion: MotionPlayer[PoseEvent]) -> tuple[float, ...] | None:
        """The picture's pose now: from the pose before the one shown (at the moment that
        one fell due) to it (when the next falls due), so the drawing follows the clock one
        step behind the poses; None once the next is due (draw the pose itself)."""
        if self._segment is None or motion.start_time is None or math.isinf(motion.rate):
            return None
        fraction = (self.clock() - motion.start_time) * motion.rate - motion.index
        if fraction >= 1.0:
            return None
        from valterm.core.kinematics import joints_between  # loaded with the session (the start)

        return joints_between(*self._segment, max(0.0, fraction))

    def _motion_step(self, pace: bool) -> float | None:
        """Show the pose due now; the seconds to wait, or None once the motion is over."""
        motion = self._motion
        assert motion is not None
        if self._aborting or not pace:
            motion.skip_to_end()
        elif motion.poll() is not None:
            self._scene_changed = True
        if not motion.finished:
            between = self._in_between(motion) if pace and not self._aborting else None
            if between != self._between:
                self._between, self._picture_changed = between, True
            # the next picture at the stream's next frame (a late tick does not push the
            # later ones back), the next pose not before it: a pose falling due
            # between two frames is drawn at the next, not as a frame of its own; at most
            # 0.1 s without a fresh look at the clock (as for DELAY)
            frame = self._to_next_frame()
            return min(frame if between is not None else max(motion.next_due_in(), frame), 0.1)
        self._motion, self._between, self._segment = None, None, None
        self._scene_changed = True
        tail, self._after_motion = self._after_motion, []
        for event in tail:
            self._take(event, pace)
        return None

    def _frame_now(self) -> int:
        """The stream's frame now: frames fall at whole multiples of 1 / DRAW_RATE from its
        start; a tick a quarter of a frame early is in the frame it is early for (a timer
        that fires early)."""
        return math.floor((self.clock() - self._frame_origin) * DRAW_RATE + 0.25)

    def _to_next_frame(self) -> float:
        """Seconds to the stream's next frame (one close ahead is skipped)."""
        period = 1.0 / DRAW_RATE
        return (self._frame_now() + 1) * period - (self.clock() - self._frame_origin)

    def _picture_held(self) -> float | None:
        """Seconds a picture must wait: None when it may be posted now (no picture yet in
        this frame of the stream's clock; the frame is then taken)."""
        frame = self._frame_now()
        if self._last_frame is not None and frame <= self._last_frame:
            return max(YIELD, self._to_next_frame())
        self._last_frame = frame
        return None

    def _post_lines(self) -> None:
        if self._lines and self._post is not None:
            lines = list(self._lines)
            self._lines.clear()
            self._post(TranscriptLines(lines))

    def _flush(self, pace: bool = False) -> float | None:
        """Post this tick's lines and redraw (and a pause or the end). While paced, at most
        one picture a frame: the seconds the picture waits, or None (posted, or none)."""
        post = self._post
        if post is None:
            return None
        self._post_lines()
        held = None
        if pace and self.playing and not self._paused and (self._scene_changed or self._picture_changed):
            held = self._picture_held()
        if held is None:  # (held: drawn at the next frame, the flags stay)
            self._post_picture(post)
        if self._last_pause is not None:
            pause, self._last_pause = self._last_pause, None
            post(RunPaused(pause))
        if self._ended is not None:
            aborted, self._ended = self._ended, None
            self._post = None
            post(RunEnded(aborted))
        return held

    def _post_picture(self, post: Post) -> None:
        """The redraw this tick's poses ask for: the screen (a pose), or the picture alone."""
        if self._scene_changed:
            self._scene_changed = self._picture_changed = False
            post(SceneShown())
        elif self._picture_changed:
            self._picture_changed = False
            post(PictureMoved())

    def _end(self, aborted: bool) -> None:
        source, self._source = self._source, None
        self.end_tick = self.ticks
        self._motion, self._after_motion, self._resume_at = None, [], None
        self._between = self._segment = None
        self._paused = False
        self._stop_source = None
        if self._timer is not None:
            self._timer.cancel()
            self._timer = None
        self._scene_changed = True
        self._ended = aborted
        self._last_pause = None
        if isinstance(source, Generator):
            try:
                source.close()  # a generator ends where it stood (its finally runs now)
            except Exception as error:
                self._lines.append(problem_text(error))
        self._flush()


def show_at_once(events: Iterable[Event], take: Callable[[Event], bool]) -> list[str]:
    """A short stream worked through now, no pacing (a command typed while a program is
    paused): its lines (the same renderer's as the player's), the events ``take`` took
    aside. Poses only move the robot: the caller redraws once."""
    lines: list[str] = []
    try:
        for event in events:
            if isinstance(event, (PoseEvent, Delay)) or (isinstance(event, _OWN_EVENTS) and take(event)):
                continue
            lines.extend(event_lines(event))
    except Exception as error:
        lines.append(problem_text(error))
    return lines[-TRANSCRIPT_LINES:]
