// SPDX-License-Identifier: LGPL-2.1-or-later
// What scripts (the browser tests, benchmarks) may do to the viewer, on
// window.caustic beside the state the page keeps: each hook takes the same
// path as the control it stands for, so a test of the hook tests the page.
// `parts` returns the viewer's current room, controls, parameter channel,
// stream and session (they change on reconnect), and its loading steps.
import { drawnCentre, drawnHeights, pagePoint, surfaceTiles, waterPagePoint } from './test_probes.js';

export function installTestHooks(state, parts) {
  // A light drag: the marker moves, the light follows it.
  state.moveLight = (dx, dy, dz) => {
    const { room, channel } = parts();
    room.lightMarker.position.add({ x: dx, y: dy, z: dz });
    channel.set({ light: room.lightFromMarker(state.params.light.type) });
  };
  // The panel's controls.
  state.setParams = (patch) => parts().channel.set(patch);
  state.resetScene = () => parts().resetScene();
  // A move-gizmo drag.
  state.moveObject = (dx, dy, dz) => {
    const { room, channel } = parts();
    room.handle.position.add({ x: dx, y: dy, z: dz });
    channel.set({ object: room.objectPose() });
  };
  // A rotate-gizmo drag (degrees about the object's own axes, XYZ order).
  state.rotateObject = (dx, dy, dz) => {
    const { room, channel } = parts();
    const r = room.handle.rotation;
    r.set(r.x + dx * Math.PI / 180, r.y + dy * Math.PI / 180, r.z + dz * Math.PI / 180, 'XYZ');
    channel.set({ object: room.objectPose() });
  };
  // Where the light marker and the object's handle are on the page (pointer and touch tests).
  state.pagePoint = (what) => {
    const { room } = parts();
    return pagePoint(room, what === 'light' ? room.lightMarker : room.handle);
  };
  // The screen's and the receivers' lightmaps: centre, geometry type, tile offset and repeat.
  state.surfaces = () => surfaceTiles(parts().room);
  // Where the slab is drawn (scene coordinates of its centre).
  state.drawnProxy = () => drawnCentre(parts().room);
  // The camera: where it is, how far from what it orbits, and an orbit
  // step (radians about the vertical) ending as a drag ends.
  state.cameraPosition = () => parts().room.camera.position.toArray();
  state.cameraDistance = () => {
    const { room, controls } = parts();
    return room.camera.position.distanceTo(controls.orbit.target);
  };
  state.orbitBy = (angle) => {
    const { room, controls } = parts();
    const offset = room.camera.position.clone().sub(controls.orbit.target);
    offset.applyAxisAngle({ x: 0, y: 1, z: 0 }, angle);
    room.camera.position.copy(controls.orbit.target).add(offset);
    controls.orbit.update();
    controls.orbit.dispatchEvent({ type: 'end' });
  };
  // A scene with water: the heights drawn (metres, the frame message's
  // order), where the water's point (x, y) is on the page, a click there
  // (the click's own path: raycast, then the drop's POST), and the POST
  // alone at any (x, y), as a click that met the water there would send it.
  // Both resolve to the server's answer { status, body }; a click that
  // missed the water, to null. What was drawn last is window.caustic.water.
  state.waterHeights = () => (parts().water ? drawnHeights(parts().water.surface) : null);
  state.waterPagePoint = (x, y) => waterPagePoint(parts().water.surface, x, y);
  state.clickWater = (x, y) => {
    const { water } = parts();
    return water.click(...waterPagePoint(water.surface, x, y));
  };
  state.dropAt = (x, y) => parts().water.drop(x, y);
  // The session's id and codec, never its token.
  Object.defineProperty(state, 'session', {
    get: () => {
      const s = parts().session;
      return s && { id: s.id, codec: s.codec };
    },
  });
  // The stream's peer connection (its statistics, its descriptions).
  Object.defineProperty(state, 'peer', { get: () => parts().stream?.pc });
  // The loading steps: those under way, else the last load's.
  state.loading = () => {
    const { loading } = parts();
    return loading.timer ? loading.summary() : loading.last ?? [];
  };
  // Closes the signalling socket as a network failure would.
  state.dropSignalling = () => parts().stream?.socket.close();
  // Hangs the peer connection up first, the socket left open: the server
  // hears of it from the data channel's association ending.
  state.closePeer = () => parts().stream?.pc.close();
}
