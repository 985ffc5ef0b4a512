// SPDX-License-Identifier: LGPL-2.1-or-later
// The REST API: sessions, coalesced parameter patches and drops in a pool's water.

export class ServerFull extends Error {}
// A refusal that asking again will not change (an unknown scene, a bad codec).
export class Refused extends Error {}

// `home`: '' or '/i/<n>', the instance that must hold the session (the
// one that keeps a visitor's design, behind a proxy).
export async function createSession(scene, codec, home = '') {
  const response = await fetch(`${home}/api/v1/sessions`, {
    method: 'POST',
    headers: { 'Content-Type': 'application/json' },
    body: JSON.stringify({ scene, codec }),
  });
  const body = await response.json();
  if (response.status === 503) throw new ServerFull(body.detail);
  if (response.status >= 400 && response.status < 500 && response.status !== 408 && response.status !== 429)
    throw new Refused(body.detail ?? `the server answered ${response.status}`);
  if (!response.ok) throw new Error(body.detail ?? `the server answered ${response.status}`);
  return body;
}

// A session's own URL: behind a proxy it names the instance that holds it.
const sessionUrl = (session) => session.url ?? `/api/v1/sessions/${session.id}`;

// Ends a session; keepalive lets it go out while the page unloads.
export function deleteSession(session) {
  return fetch(sessionUrl(session), {
    method: 'DELETE',
    keepalive: true,
    headers: { Authorization: `Bearer ${session.token}` },
  }).catch(() => {});
}

// Drops a stone in the session's water ({ x, y } in metres, optional
// strength and radius): { ok, status, body }, the body the server's answer
// or its problem (409: no water, 422: a bad value, 429: too many waiting).
export async function postDrop(session, drop) {
  const response = await fetch(`${sessionUrl(session)}/drops`, {
    method: 'POST',
    headers: { 'Content-Type': 'application/json', Authorization: `Bearer ${session.token}` },
    body: JSON.stringify(drop),
  });
  const body = await response.json().catch(() => ({}));
  return { ok: response.ok, status: response.status, body };
}

// Merges `patch` into `target` as a merge patch would. Every key becomes an
// own property, "__proto__" included (JSON.parse makes it one, and a plain
// assignment would set the target's prototype instead: a shared link's
// {"__proto__": ...} reached Object.prototype); the server then refuses the
// key by name. Only own values are merged into, never inherited ones.
function merge(target, patch) {
  for (const [key, value] of Object.entries(patch)) {
    const own = Object.hasOwn(target, key) ? target[key] : undefined;
    const merged = value && typeof value === 'object' && !Array.isArray(value)
      ? merge(own && typeof own === 'object' ? own : {}, value) : value;
    Object.defineProperty(target, key, { value: merged, enumerable: true, writable: true, configurable: true });
  }
  return target;
}

// Sends parameter changes with at most one PATCH in flight: changes that
// arrive meanwhile are merged, and the latest state wins.
export class ParamChannel {
  constructor(session, { onApplied, onError }) {
    this.session = session;
    this.pending = null;
    this.inFlight = false;
    this.onApplied = onApplied;
    this.onError = onError;
    this.closed = false;
  }

  set(patch) {
    if (this.closed) return;
    this.pending = merge(this.pending ?? {}, patch);
    if (!this.inFlight) this.flush();
  }

  // The session is gone: nothing more is sent, and answers still on their
  // way are not reported (they would speak of the old session).
  close() {
    this.closed = true;
    this.pending = null;
  }

  async flush() {
    while (this.pending) {
      const patch = this.pending;
      this.pending = null;
      this.inFlight = true;
      const sentAt = performance.now();
      try {
        const response = await fetch(`${sessionUrl(this.session)}/params`, {
          method: 'PATCH',
          headers: { 'Content-Type': 'application/merge-patch+json', Authorization: `Bearer ${this.session.token}` },
          body: JSON.stringify(patch),
        });
        const body = await response.json();
        if (this.closed) return;
        if (response.ok) this.onApplied(body, sentAt);
        else this.onError(body);
      } catch (error) {
        if (!this.closed) this.onError({ detail: error.message });
      } finally {
        this.inFlight = false;
      }
    }
  }
}
