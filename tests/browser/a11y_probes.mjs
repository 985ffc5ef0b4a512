// SPDX-License-Identifier: LGPL-2.1-or-later
// What the accessibility tests read from a page: functions that run inside
// it (passed to page.evaluate, until or addInitScript).

export const live = () => window.caustic.connection === 'live' && window.caustic.shownVersion >= 1;

// What has the focus, by the name a test knows it by.
export const focused = () => {
  const e = document.activeElement;
  return e.id || e.dataset.mode || e.getAttribute('aria-label') || e.textContent.trim().slice(0, 30);
};

// What a screen reader reads of the element `selector`: its text less the
// parts hidden from it.
export const readable = (selector) => {
  const read = (node) => (node.nodeType === Node.TEXT_NODE ? node.textContent
    : node.getAttribute?.('aria-hidden') === 'true' ? '' : [...node.childNodes].map(read).join(''));
  return read(document.querySelector(selector));
};

// Whether two elements' boxes overlap.
export const overlap = ([a, b]) => {
  const [r, s] = [document.querySelector(a).getBoundingClientRect(), document.querySelector(b).getBoundingClientRect()];
  return r.left < s.right && s.left < r.right && r.top < s.bottom && s.top < r.bottom;
};

// The shown targets in the header smaller than 24x24 CSS px (WCAG 2.2
// 2.5.8), as "name WxH".
export const smallTargets = () => [...document.querySelectorAll('#hud a, #hud button')].filter((t) => t.offsetParent)
  .map((t) => [t.id || t.textContent, t.getBoundingClientRect()]).filter(([, r]) => r.width < 24 || r.height < 24)
  .map(([name, r]) => `${name} ${r.width}x${r.height}`);

// An init script: window.stateReads gets each change of what a screen
// reader reads of the state line (#state), as it happens.
export const recordStateReads = () => {
  window.stateReads = [];
  const read = (node) => (node.nodeType === Node.TEXT_NODE ? node.textContent
    : node.getAttribute?.('aria-hidden') === 'true' ? '' : [...node.childNodes].map(read).join(''));
  new MutationObserver(() => {
    const label = document.getElementById('state');
    const now = label && read(label);
    if (now && now !== window.stateReads.at(-1)) window.stateReads.push(now);
  }).observe(document, { subtree: true, childList: true, characterData: true, attributes: true });
};
