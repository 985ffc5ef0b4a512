// SPDX-License-Identifier: LGPL-2.1-or-later
// The address as a shareable link: ?scene=ID&codec=C&p=PARAMS&view=CAMERA.
// `p` holds only what the visitor changed (a merge patch against the
// scene's own values, numbers to five digits), `view` the camera and what
// it orbits. A reload or a shared link restores both; the server checks `p`
// like any patch.

// Keys the server decides for itself: fidelity "auto" picks these, and a
// screen that follows the light places its own centre. Sharing them would
// only bring back a warning that they are overridden.
const AUTO_KEYS = { render: ['mesh_resolution', 'fresnel'], light: ['point_model'] };
const SECTIONS = ['object', 'light', 'screen', 'render', 'post', 'water'];  // water: only a pool's

const round = (v) => (typeof v === 'number' ? Number(v.toPrecision(5)) : Array.isArray(v) ? v.map(round) : v);

function derived(section, key, now) {
  if (section === 'screen') return key === 'center' && now.screen.follow_light;
  return now.render.fidelity === 'auto' && (AUTO_KEYS[section] ?? []).includes(key);
}

/// What `now` changes against `origin` (both scene-format params).
export function changedParams(origin, now) {
  const patch = {};
  for (const section of SECTIONS) {
    for (const [key, value] of Object.entries(now[section] ?? {})) {
      if (derived(section, key, now)) continue;
      if (JSON.stringify(round(value)) === JSON.stringify(round(origin[section]?.[key]))) continue;
      (patch[section] ??= {})[key] = round(value);
    }
  }
  return patch;
}

/// The patch a link carries, or null (absent, or not a JSON object).
export function sharedParams(query) {
  try {
    const p = JSON.parse(query.get('p') ?? 'null');
    return p && typeof p === 'object' && !Array.isArray(p) ? p : null;
  } catch {
    return null;
  }
}

/// The camera a link carries: [x, y, z, target x, y, z], or null.
export function sharedView(query) {
  const v = (query.get('view') ?? '').split(',').map(Number);
  return v.length === 6 && v.every(Number.isFinite) ? v : null;
}

/// Writes the current state into the address bar without a new history entry.
export function writeAddress({ patch, camera, target, codec }) {
  const url = new URL(location.href);
  url.searchParams.set('codec', codec);
  if (patch && Object.keys(patch).length) url.searchParams.set('p', JSON.stringify(patch));
  else url.searchParams.delete('p');
  if (camera) url.searchParams.set('view', [...camera.toArray(), ...target.toArray()].map((x) => x.toFixed(1)).join(','));
  history.replaceState(null, '', url);
  return url.href;
}
