// SPDX-License-Identifier: LGPL-2.1-or-later
// The header wraps onto more lines on a narrow screen, with larger text or
// a long error; what sits below it (the panel, the warnings) reads its
// height from --header-height so that it never hides the header's words.

export function followHeaderHeight(header = document.getElementById('hud')) {
  const set = () => document.documentElement.style.setProperty('--header-height', `${Math.ceil(header.getBoundingClientRect().height)}px`);
  new ResizeObserver(set).observe(header);
  set();
}
