// SPDX-License-Identifier: LGPL-2.1-or-later
// The header's connection state (viewer and broadcast pages): a live region
// (role=status) that a screen reader reads when the state or its reason
// changes. A retry's countdown goes in a part of it that is hidden from
// screen readers: otherwise the whole line would be read again every second.

/// Shows `name` (connecting, live, reconnecting, full, error), `detail` (why)
/// and `countdown` (e.g. "retrying in 3 s": seen, not read) in `label`.
export function showState(label, name, detail = '', countdown = '') {
  if (!label.querySelector('.said')) {
    const said = document.createElement('span');
    said.className = 'said';
    const seen = document.createElement('span');
    seen.className = 'countdown';
    seen.setAttribute('aria-hidden', 'true');
    label.replaceChildren(said, seen);
  }
  label.dataset.state = name;
  const said = label.querySelector('.said');
  const text = detail ? `${name}: ${detail}` : name;
  // Written only when it changes: a rewrite of the same words is read again.
  if (said.textContent !== text) said.textContent = text;
  label.querySelector('.countdown').textContent = countdown ? `; ${countdown}` : '';
}
