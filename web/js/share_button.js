// SPDX-License-Identifier: LGPL-2.1-or-later
// The viewer's Share button: copies the link to what is on screen (share.js)
// and says so in a live region, since a button's changed words are not read
// out. Where the page may not write the clipboard (an address that is not a
// secure context, a denied permission) the link is shown selected in a
// labelled read-only field below the header, to copy by hand: a prompt
// would take the page away and read as an error.

const SAID_MS = 2000;  // how long "Link copied" shows on the button

/// Wires #share; `link()` brings the address up to date and returns it.
export function installShareButton(link) {
  const button = document.getElementById('share');
  const said = document.getElementById('share-said');
  const panel = document.getElementById('share-panel');
  const field = document.getElementById('share-url');
  let timer = null;
  const close = () => {
    panel.hidden = true;
    button.focus();
  };
  button.addEventListener('click', async () => {
    const href = link();
    clearTimeout(timer);
    try {
      await navigator.clipboard.writeText(href);
      panel.hidden = true;
      button.textContent = said.textContent = 'Link copied';
    } catch {
      field.value = href;
      panel.hidden = false;
      field.focus();
      field.select();
      said.textContent = 'The page cannot copy here: the link is selected in the field below, to copy by hand';
    }
    // Emptied (which is not read out), so that the next press is read again.
    timer = setTimeout(() => { button.textContent = 'Share'; said.textContent = ''; }, SAID_MS);
  });
  field.addEventListener('keydown', (e) => {
    if (e.key !== 'Escape') return;
    e.preventDefault();
    close();
  });
  document.getElementById('share-close').addEventListener('click', close);
}
