// The home page: one card per scene from GET /api/v1/scenes; a card opens
// the viewer, which starts the session.
const list = document.getElementById('scenes');
const status = document.getElementById('gallery-status');
const codec = document.getElementById('codec');

async function load() {
  try {
    const response = await fetch('/api/v1/scenes');
    if (!response.ok) throw new Error(`the server answered ${response.status}`);
    const { scenes } = await response.json();
    for (const scene of scenes) {
      const card = document.createElement('a');
      card.className = 'card';
      card.dataset.scene = scene.id;
      card.href = `viewer.html?scene=${encodeURIComponent(scene.id)}`;
      card.addEventListener('click', (event) => {
        event.preventDefault();
        location.href = `${card.href}&codec=${codec.value}`;
      });
      const img = document.createElement('img');
      img.src = scene.thumbnail;
      img.alt = `Caustic of ${scene.name}`;
      const title = document.createElement('h2');
      title.textContent = scene.name;
      const text = document.createElement('p');
      text.textContent = scene.description;
      card.append(img, title, text);
      list.append(card);
    }
    status.textContent = `${scenes.length} scenes`;
  } catch (error) {
    status.textContent = `Cannot load the scenes: ${error.message}`;
  }
}

load();
