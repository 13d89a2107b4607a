"""The lights controller: animation queue, segments and panel frames, stepped at 50 Hz.

Queue rules (manual): priority 1 interrupts and removes animations of priority 2 and 3;
2 interrupts 3; 3 is added at the end. An animation waiting longer than its ``timeout``
is dropped. An interrupted animation that had played less than 65 % goes back to the queue.
A repeating animation becomes its segments' background: it plays whenever nothing else does.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from panther_ops.manager.errors import LightsConfigError
from panther_ops.manager.lights.animations import Playback, part_frames
from panther_ops.manager.lights.config import (
    CONTROLLER_FREQUENCY,
    DEFAULT_PRIORITY,
    AnimationDesc,
    LedConfig,
    Segment,
)

MAX_QUEUE = 10
RESUME_BELOW_PROGRESS = 0.65
RGB = tuple[int, int, int]


class SegmentState:
    """What one segment plays: the current animation and the repeating background."""

    def __init__(self, segment: Segment) -> None:
        self.segment = segment
        self.animation: Playback | None = None
        self.background: Playback | None = None
        self.animation_finished = False
        self.animation_name: str | None = None
        self.background_name: str | None = None

    def set_animation(self, playback: Playback, repeating: bool, name: str) -> None:
        self.animation = playback
        self.animation_name = name
        self.animation_finished = False
        if repeating:
            self.background = playback
            self.background_name = name
            self.animation_finished = True
        if self.background is not None:
            self.background.reset()

    def update(self) -> None:
        if self.animation is None:
            return
        if self.animation.finished:
            self.animation_finished = True
        use_background = self.animation_finished and self.background is not None
        playing = self.background if use_background and self.background else self.animation
        if use_background and playing.finished:
            playing.reset()
        playing.update()

    def playing(self) -> Playback | None:
        if self.background is not None and self.animation_finished:
            return self.background
        return self.animation

    def playing_name(self) -> str | None:
        if self.background is not None and self.animation_finished:
            return self.background_name
        return self.animation_name

    def colours(self) -> list[RGB]:
        playback = self.playing()
        shown = playback.colours() if playback is not None else None
        if shown is None:
            return [(0, 0, 0)] * self.segment.num_leds
        return list(shown[::-1] if self.segment.inverted else shown)


@dataclass
class QueuedAnimation:
    """An animation request (the C++ LEDAnimation)."""

    desc: AnimationDesc
    init_time: float
    repeating: bool
    param: str
    segments: list[SegmentState] = field(default_factory=list)

    @property
    def priority(self) -> int:
        return self.desc.priority

    def progress(self) -> float:
        return min((s.animation.progress for s in self.segments if s.animation), default=1.0)

    def finished(self) -> bool:
        return all(s.animation_finished for s in self.segments)

    def reset(self, now: float) -> None:
        for state in self.segments:
            if state.animation is not None:
                state.animation.reset()
            state.animation_finished = False
        self.init_time = now


class AnimationQueue:
    """Waiting animations, ordered by priority then arrival."""

    def __init__(self, size: int = MAX_QUEUE) -> None:
        self.size = size
        self.items: list[QueuedAnimation] = []

    def put(self, item: QueuedAnimation, now: float) -> None:
        if item.priority == 1:
            self.items = [i for i in self.items if i.priority < 2]
        self.validate(now)
        if len(self.items) >= self.size:
            raise LightsConfigError("Animation queue overloaded")
        self.items.append(item)
        self.items.sort(key=lambda i: (i.priority, i.init_time))

    def get(self) -> QueuedAnimation:
        return self.items.pop(0)

    def validate(self, now: float) -> None:
        """Drop animations that waited longer than their timeout."""
        self.items = [i for i in self.items if now - i.init_time <= i.desc.timeout]

    def first_priority(self) -> int:
        return self.items[0].priority if self.items else DEFAULT_PRIORITY


class LightsController:
    """Queue, segments and panels; `advance(now)` runs the 50 Hz steps up to `now`."""

    def __init__(self, config: LedConfig, frequency: float = CONTROLLER_FREQUENCY,
                 start: float = 0.0) -> None:
        self.config = config
        self.frequency = frequency
        self.segments = {name: SegmentState(s) for name, s in config.segments.items()}
        self.queue = AnimationQueue()
        self.current: QueuedAnimation | None = None
        self.animation_finished = True
        self.next_step = start
        self.steps = 0

    def set_animation(self, anim_id: int, param: str, repeating: bool, now: float) -> tuple[bool, str]:
        """The SetLEDAnimation service: queue an animation by ID."""
        desc = self.config.animations.get(anim_id)
        if desc is None:
            return False, f"No animation with ID: {anim_id}"
        item = QueuedAnimation(desc, now, repeating, param)
        try:
            self.queue.put(item, now)
        except LightsConfigError as exc:
            return False, str(exc)
        return True, ""

    def _start(self, item: QueuedAnimation) -> None:
        states: list[SegmentState] = []
        for part in item.desc.parts:
            for name in part.segments:
                state = self.segments[name]
                frames = part_frames(part, state.segment.num_leds, self.frequency, item.param)
                state.set_animation(Playback(frames), item.repeating, item.desc.name)
                states.append(state)
        item.segments = states
        self.current = item

    def step(self, now: float) -> None:
        """One controller cycle (ControllerTimerCB)."""
        self.steps += 1
        if self.animation_finished:
            self.queue.validate(now)
            if self.queue.items:
                item = self.queue.get()
                try:
                    self._start(item)
                except LightsConfigError:
                    self.current = None
        if self.current is None:
            return
        if self.current.priority > self.queue.first_priority():
            if self.current.progress() < RESUME_BELOW_PROGRESS:
                self.current.reset(now)
                self.queue.put(self.current, now)
            self.animation_finished = True
            return
        for state in self.segments.values():
            state.update()
        self.animation_finished = self.current.finished()

    def advance(self, now: float) -> None:
        """Run every 50 Hz step due up to `now`."""
        period = 1.0 / self.frequency
        while self.next_step <= now + 1e-9:
            self.step(self.next_step)
            self.next_step += period

    def panel_colours(self) -> dict[int, list[RGB]]:
        """What each panel (channel) shows now, LED by LED."""
        panels = {c: [(0, 0, 0)] * p.number_of_leds for c, p in self.config.panels.items()}
        for state in self.segments.values():
            seg = state.segment
            panels[seg.channel][seg.offset:seg.offset + seg.num_leds] = state.colours()
        return panels

    def showing(self) -> dict[str, str | None]:
        """Name of the animation each segment plays now (its background when idle)."""
        return {name: state.playing_name() for name, state in self.segments.items()}
