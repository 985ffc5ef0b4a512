// SPDX-License-Identifier: LGPL-2.1-or-later
// The steps between opening the page (or losing the stream) and the first
// frame, each with the seconds it took, so a slow start says where it is
// rather than only "connecting".

export class LoadingSteps {
  constructor(element) {
    this.element = element;
    this.steps = [];
  }

  /// Ends the step under way (if any) and starts `name`.
  begin(name) {
    const now = performance.now();
    if (!this.timer) this.timer = setInterval(() => this.draw(), 200);
    this.finish(now);
    this.steps.push({ name, begin: now });
    this.element.hidden = false;
    this.draw();
  }

  /// The first frame is on screen: the list goes away until the next start.
  done() {
    if (!this.timer) return;
    this.finish(performance.now());
    clearInterval(this.timer);
    this.timer = null;
    this.draw();
    this.element.hidden = true;
    this.last = this.summary();
    this.steps = [];
  }

  /// The start failed for good: the list goes away, its steps kept for the tests.
  stop() {
    if (!this.timer) return;
    this.finish(performance.now());
    clearInterval(this.timer);
    this.timer = null;
    this.element.hidden = true;
    this.last = this.summary();
    this.steps = [];
  }

  finish(now) {
    const current = this.steps.at(-1);
    if (current && current.end === undefined) current.end = now;
  }

  /// [{ name, seconds, done }] for the page's state (and the tests).
  summary() {
    const now = performance.now();
    return this.steps.map((s) => ({ name: s.name, seconds: ((s.end ?? now) - s.begin) / 1000, done: s.end !== undefined }));
  }

  draw() {
    const items = this.summary().map(({ name, seconds, done }) => {
      const li = document.createElement('li');
      li.className = done ? 'done' : 'active';
      li.textContent = `${name} ${seconds.toFixed(1)} s`;
      return li;
    });
    this.element.replaceChildren(...items);
  }
}
