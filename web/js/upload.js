// SPDX-License-Identifier: LGPL-2.1-or-later
// The gallery's "upload your picture" card: the picture goes to
// POST /api/v1/designs, its progress is polled, and the finished design
// opens in the viewer like any other scene.
import { bodyOf } from './api.js';
import { transient } from './retry.js';

const POLL_MS = 500;
// A design takes minutes at most (the server's queue holds a few); past
// this the page stops asking and says so. Polls that get no answer (a
// network blip, a proxy between restarts) are asked again, up to a few
// in a row.
const FOLLOW_MS = 15 * 60 * 1000;
const BLIPS_IN_A_ROW = 5;

export function uploadCard(codecOf) {
  const card = document.createElement('form');
  card.className = 'card upload';
  card.id = 'upload';
  card.innerHTML = `
    <div class="drop"><span>Your picture, as glass</span></div>
    <h3>Upload your picture</h3>
    <p>A PNG or JPEG becomes a lens whose caustic draws it; it opens here when it is ready.</p>
    <label>Name <input name="name" maxlength="64" value="My picture" required></label>
    <label title="Tinted glass: each part of the picture's light keeps its colour">
      <input type="checkbox" name="colour"> In colour</label>
    <label>Picture <input type="file" name="picture" accept="image/png,image/jpeg" required></label>
    <progress max="1" value="0" aria-label="Design progress" hidden></progress>
    <p class="upload-status" role="status"></p>`;
  const file = card.querySelector('input[type=file]');
  const bar = card.querySelector('progress');
  const status = card.querySelector('.upload-status');
  // A live region: written only when the words change, or each poll would read them again.
  const say = (text) => { if (status.textContent !== text) status.textContent = text; };
  // Enter in the name field would submit the form and reload the page.
  card.addEventListener('submit', (event) => event.preventDefault());

  file.addEventListener('change', async () => {
    const picture = file.files[0];
    if (!picture) return;
    if (picture.type !== 'image/png' && picture.type !== 'image/jpeg') {
      say('Only PNG and JPEG pictures are taken.');
      return;
    }
    file.disabled = true;
    bar.hidden = false;
    bar.value = 0;
    say('Uploading…');
    try {
      const name = card.querySelector('input[name=name]').value || 'My picture';
      const colour = card.querySelector('input[name=colour]').checked;
      const response = await fetch(`/api/v1/designs?name=${encodeURIComponent(name)}&colour=${colour}`, {
        method: 'POST', headers: { 'Content-Type': picture.type }, body: picture,
      });
      const answer = await bodyOf(response);
      if (!response.ok) throw new Error(answer.detail ?? `the server answered ${response.status}`);
      if (!answer.status_url) throw new Error(`the server answered ${response.status} without a design`);
      const design = await follow(answer.status_url, (d) => {
        bar.value = d.progress;
        say(d.state === 'queued' ? `Waiting in line (position ${d.position})…` : `Designing: ${d.stage ?? d.state}…`);
      });
      const ssim = design.report?.engine?.ssim;
      say(`Ready${ssim ? ` (SSIM ${ssim.toFixed(3)})` : ''}: opening…`);
      // Behind a proxy the design is kept by the instance its status URL names.
      const instance = answer.status_url.match(/^\/i\/([0-9]+)\//)?.[1];
      location.href = `viewer.html?scene=${encodeURIComponent(design.scene)}&codec=${codecOf()}` +
        (instance ? `&instance=${instance}` : '');
    } catch (error) {
      say(`Not designed: ${error.message}`);
      bar.hidden = true;
    } finally {
      file.disabled = false;
      // Emptied, so that picking the same file again (after a refusal, say
      // a full queue) is a change and tries again.
      file.value = '';
    }
  });
  return card;
}

// Polls a design until it is ready or failed; `onProgress` sees each state.
async function follow(url, onProgress) {
  const until = performance.now() + FOLLOW_MS;
  for (let blips = 0; ; ) {
    if (performance.now() > until) throw new Error('it is taking too long; try again later');
    let response = null, design = {};
    try {
      response = await fetch(url);
      design = await bodyOf(response);
    } catch {
      // No answer: counted below, asked again.
    }
    const again = !response || transient(response.status);
    if (again && ++blips > BLIPS_IN_A_ROW) {
      throw new Error(response ? `the server answered ${response.status}` : 'the server does not answer');
    }
    if (!again) {
      blips = 0;
      if (!response.ok) throw new Error(design.detail ?? `the server answered ${response.status}`);
      if (design.state === 'ready') return design;
      if (design.state === 'failed') throw new Error(design.error || 'the designer could not make a lens of this picture');
      onProgress(design);
    }
    await new Promise((resolve) => { setTimeout(resolve, POLL_MS * 2 ** Math.min(blips, 4)); });
  }
}
