"""One line of progress for a long run: rewritten in place on a terminal, a plain line now and then elsewhere."""
import sys
import time


class ProgressLine:
    """show(text) as often as you like; done() ends the line. On a terminal the line is redrawn at most every
    `redraw_s`; on a pipe or file (make's output in a log) a line is printed every `every_s`."""

    def __init__(self, stream=None, redraw_s=0.5, every_s=10.0):
        self.stream = stream or sys.stdout
        self.tty = self.stream.isatty()
        self.interval = redraw_s if self.tty else every_s
        self.last_shown = None
        self.text = None

    def show(self, text):
        self.text = text
        now = time.monotonic()
        if self.last_shown is not None and now - self.last_shown < self.interval:
            return
        self.last_shown = now
        self.stream.write(f"\r{text}\x1b[K" if self.tty else f"{text}\n")
        self.stream.flush()

    def done(self):
        """End the progress line (the last text stays on screen), so that what follows starts on a line of its own."""
        if self.tty and self.text is not None:
            self.stream.write(f"\r{self.text}\x1b[K\n")
            self.stream.flush()
        self.last_shown = self.text = None
