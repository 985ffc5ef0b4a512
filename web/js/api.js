// SPDX-License-Identifier: LGPL-2.1-or-later
// The REST API: sessions, coalesced parameter patches and drops in a pool's water.
import { retryAfterMs, retryDelay, transient } from './retry.js';

// Errors may carry `retryAfterMs`: the wait the server asked for (Retry-After).
export class ServerFull extends Error {}
// A refusal that asking again will not change (an unknown scene, a bad codec).
export class Refused extends Error {}

// An answer's body: read as JSON only when it says it is, since a proxy in
// front of the server answers its own errors (a 502) in HTML.
export async function bodyOf(response) {
  if (!/json/i.test(response.headers.get('content-type') ?? '')) return {};
  return response.json().catch(() => ({}));
}

const detailOf = (response, body) => body.detail ?? `the server answered ${response.status}`;
const waitOf = (response) => retryAfterMs(response.headers.get('retry-after'));

// `home`: '' or '/i/<n>', the instance that must hold the session (the
// one that keeps a visitor's design, behind a proxy).
export async function createSession(scene, codec, home = '') {
  const response = await fetch(`${home}/api/v1/sessions`, {
    method: 'POST',
    headers: { 'Content-Type': 'application/json' },
    body: JSON.stringify({ scene, codec }),
  });
  const body = await bodyOf(response);
  const error = (Kind) => Object.assign(new Kind(detailOf(response, body)), { retryAfterMs: waitOf(response) });
  if (response.status === 503) throw error(ServerFull);
  if (response.status >= 400 && !transient(response.status)) throw error(Refused);
  if (!response.ok) throw error(Error);
  return body;
}

// The session's parameters as the server holds them ({version, params, ...}).
export async function getParams(session) {
  const response = await fetch(`${sessionUrl(session)}/params`, { headers: { Authorization: `Bearer ${session.token}` } });
  const body = await bodyOf(response);
  if (!response.ok) throw new Error(detailOf(response, body));
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
  const body = await bodyOf(response);
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

// Whether `later` merged over `earlier` says what the two say one after the
// other. It does not where `earlier` restores a section (null) that `later`
// then sets keys of: merged, the keys would be set without the restore.
function composable(earlier, later) {
  return Object.entries(later).every(([key, value]) => {
    if (!value || typeof value !== 'object' || Array.isArray(value) || !Object.hasOwn(earlier, key)) return true;
    const before = earlier[key];
    return before !== null && typeof before === 'object' && !Array.isArray(before) && composable(before, value);
  });
}

// `patch` onto the end of `queue`: merged into the last patch where the two
// compose, else after it.
function enqueue(queue, patch) {
  const last = queue.at(-1);
  if (last && composable(last, patch)) merge(last, patch);
  else queue.push(merge({}, patch));
}

// A patch the server could not take now (a timeout, too many requests, a
// server error or a proxy between restarts: transient(), or no answer)
// goes again after a wait, merged under the changes made meanwhile where
// they compose; after PATCH_TRIES tries it is given up.
const PATCH_TRIES = 5;

// Sends parameter changes with at most one PATCH in flight: changes that
// arrive meanwhile are merged (queued behind a restore they would undo),
// and the latest state wins. Callbacks:
// onApplied(answer, sentAt); onError(problem) for a refusal that asking
// again would not change; onRetrying(problem, waitMs) before a patch goes
// again; onGaveUp(problem) when it will not (the server holds what it held).
export class ParamChannel {
  constructor(session, { onApplied, onError, onRetrying = () => {}, onGaveUp = () => {} }) {
    Object.assign(this, { session, onApplied, onError, onRetrying, onGaveUp });
    this.pending = [];  // patches not sent yet, in order; adjacent ones do not compose
    this.inFlight = false;
    this.closed = false;
    this.failures = 0;
  }

  set(patch) {
    if (this.closed) return;
    enqueue(this.pending, patch);
    if (!this.inFlight) this.flush();
  }

  // The session is gone: nothing more is sent, and answers still on their
  // way are not reported (they would speak of the old session).
  close() {
    this.closed = true;
    this.pending = [];
  }

  async flush() {
    this.inFlight = true;
    while (this.pending.length && !this.closed) {
      const patch = this.pending.shift();
      const sentAt = performance.now();
      let response = null, body = {}, problem;
      try {
        response = await fetch(`${sessionUrl(this.session)}/params`, {
          method: 'PATCH',
          headers: { 'Content-Type': 'application/merge-patch+json', Authorization: `Bearer ${this.session.token}` },
          body: JSON.stringify(patch),
        });
        body = await bodyOf(response);
        problem = { ...body, status: response.status, detail: detailOf(response, body) };
      } catch (error) {
        problem = { detail: `the server does not answer (${error.message})` };
      }
      if (this.closed) break;
      if (response?.ok) {
        this.failures = 0;
        this.onApplied(body, sentAt);
      } else if (response && !transient(response.status)) {
        this.failures = 0;
        this.onError(problem);
      } else if (++this.failures >= PATCH_TRIES) {
        this.failures = 0;
        this.onGaveUp(problem);
      } else {
        const meanwhile = this.pending;
        this.pending = [patch];
        for (const later of meanwhile) enqueue(this.pending, later);
        const wait = retryDelay(this.failures - 1, response && waitOf(response));
        this.onRetrying(problem, wait);
        await new Promise((resolve) => { setTimeout(resolve, wait); });
      }
    }
    this.inFlight = false;
  }
}
