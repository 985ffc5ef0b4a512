// SPDX-License-Identifier: LGPL-2.1-or-later
// The home page: the upload card, then one card per scene from
// GET /api/v1/scenes, designed objects first and the optics classics below;
// a card opens the viewer, which starts the session.
import { uploadCard } from './upload.js';

const designed = document.getElementById('designed');
const classics = document.getElementById('classics');
const status = document.getElementById('gallery-status');
const codec = document.getElementById('codec');

function sceneCard(scene) {
  const card = document.createElement('a');
  card.className = 'card';
  card.dataset.scene = scene.id;
  // The codec chosen is in the link itself, so that a click, a middle
  // click and Ctrl/Cmd-click (a new tab) all open what the page shows.
  const link = () => { card.href = `viewer.html?scene=${encodeURIComponent(scene.id)}&codec=${codec.value}`; };
  link();
  codec.addEventListener('change', link);
  const img = document.createElement('img');
  img.src = scene.thumbnail;
  img.alt = `Caustic of ${scene.name}`;
  const title = document.createElement('h3');  // under its group's h2
  title.textContent = scene.name;
  const text = document.createElement('p');
  text.textContent = scene.description;
  card.append(img, title, text);
  return card;
}

async function load() {
  designed.append(uploadCard(() => codec.value));
  try {
    const response = await fetch('/api/v1/scenes');
    if (!response.ok) throw new Error(`the server answered ${response.status}`);
    const { scenes } = await response.json();
    for (const scene of scenes) (scene.kind === 'designed' ? designed : classics).append(sceneCard(scene));
    classics.previousElementSibling.hidden = !classics.children.length;
    status.textContent = `${scenes.length} scenes`;
  } catch (error) {
    // fetch's own words ("Failed to fetch") say nothing to a visitor.
    const why = error instanceof TypeError ? 'the server does not answer' : error.message;
    status.textContent = `Cannot load the scenes: ${why}. Reload the page to try again.`;
    status.classList.add('error');
  }
}

load();
