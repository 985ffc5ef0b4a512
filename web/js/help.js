// SPDX-License-Identifier: LGPL-2.1-or-later
// The viewer's help (?) and fullscreen (F): buttons for pointers and touch,
// keys for keyboards.

export function installHelpAndFullscreen() {
  const helpPanel = document.getElementById('help');
  const helpButton = document.getElementById('help-button');
  let helpOpener = null;
  // The help takes the focus (a screen reader reads it, Tab starts in it)
  // and gives it back to what had it when it closes.
  const toggleHelp = () => {
    helpPanel.hidden = !helpPanel.hidden;
    helpButton.setAttribute('aria-expanded', String(!helpPanel.hidden));
    if (!helpPanel.hidden) {
      helpOpener = document.activeElement;
      helpPanel.focus();
    } else {
      helpOpener?.focus?.();
    }
  };
  const toggleFullscreen = () => {
    if (document.fullscreenElement) document.exitFullscreen().catch(() => {});
    else document.documentElement.requestFullscreen?.().catch(() => {});
  };
  helpButton.addEventListener('click', toggleHelp);
  document.getElementById('help-close').addEventListener('click', toggleHelp);
  document.getElementById('fullscreen').addEventListener('click', toggleFullscreen);
  window.addEventListener('keydown', (e) => {
    if (e.target instanceof HTMLInputElement || e.target instanceof HTMLSelectElement) return;  // typing in the panel
    if (e.ctrlKey || e.metaKey || e.altKey) return;  // the browser's own (Ctrl+F finds in the page)
    if (e.key === 'Escape' && !helpPanel.hidden) {
      e.stopImmediatePropagation();  // it closes the help only: the mode stays as it was
      return toggleHelp();
    }
    if (e.key === '?') toggleHelp();
    if (e.key === 'f' || e.key === 'F') toggleFullscreen();
  });
}
