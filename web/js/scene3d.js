// SPDX-License-Identifier: LGPL-2.1-or-later
// The room the viewer draws around the streamed caustic: floor, screen, the
// light, a plain slab standing in for the object (never the real mesh), and
// the lightmap plane that carries the video with additive blending.
// Everything sits in a group whose local axes are the server's world axes
// (z along the light's fall); the group turns that z into three.js's y-up.
import * as THREE from 'three';

import { placeShape, shapeGeometry, shapeKey, surfaceArea } from './shapes.js';
import { furnish, glassMaterial, pixelRatio, Quality, setRoomQuality } from './room.js';

const vec = (a) => new THREE.Vector3(a[0], a[1], a[2]);

// A lightmap just in front of the rectangle `s` (scene-format keys) and its
// board behind, `margin` times as large.
function placeRectangle(lightmap, board, s, margin) {
  const normal = vec(s.normal).normalize();
  const up = vec(s.up).normalize();
  const right = new THREE.Vector3().crossVectors(up, normal).normalize();
  const basis = new THREE.Matrix4().makeBasis(right, up, normal);
  lightmap.position.copy(vec(s.center)).addScaledVector(normal, 0.05);
  lightmap.quaternion.setFromRotationMatrix(basis);
  lightmap.scale.set(s.width, s.height, 1);
  board.quaternion.copy(lightmap.quaternion);
  // A board 2 units thick under the classic scenes' screens (6 to 24
  // across); a third of the width under a smaller one, such as a pool's
  // floor 2 m across, so that it stays a board.
  const thickness = Math.min(2, Math.min(s.width, s.height) / 3);
  board.position.copy(vec(s.center)).addScaledVector(normal, -thickness / 2);
  board.scale.set(s.width * margin, s.height * margin, thickness);
}

// Shows one tile (pixels, rows from the top) of a width x height picture.
function showTile(map, tile, width, height) {
  map.repeat.set(tile.width / width, tile.height / height);
  map.offset.set(tile.x / width, 1 - (tile.y + tile.height) / height);
}

export class CausticRoom {
  // `shapes`: the meshes the scene's receivers may take (receiver_meshes).
  constructor(container, video, proxy, quality = Quality.high, shapes = {}) {
    this.shapes = shapes;
    this.renderer = new THREE.WebGLRenderer({ antialias: quality === Quality.high, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(pixelRatio(quality));
    // A picture to a screen reader; what it shows is in the page's title and state.
    this.renderer.domElement.setAttribute('role', 'img');
    this.renderer.domElement.setAttribute('aria-label', '3D view of the scene: the screen with its caustic, the glass and the light');
    container.append(this.renderer.domElement);
    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(0x181c20);
    this.quality = quality;
    this.renderer.shadowMap.enabled = quality === Quality.high;
    this.camera = new THREE.PerspectiveCamera(45, 1, 1, 5000);
    this.camera.position.set(160, 140, 200);
    this.world = new THREE.Group();
    this.world.rotation.x = -Math.PI / 2;
    this.world.updateMatrixWorld();
    this.scene.add(this.world);
    this.scene.add(new THREE.HemisphereLight(0xcfd8e0, 0x202428, 0.3));

    this.screenBox = new THREE.Mesh(new THREE.BoxGeometry(1, 1, 1),
                                    new THREE.MeshStandardMaterial({ color: 0x3a3e42, roughness: 0.9 }));
    this.screenBox.castShadow = this.screenBox.receiveShadow = true;
    // Added onto the screen, drawn right after it among the opaque objects:
    // so the glass's transmission pass, which sees only those, shows the
    // caustic through the glass too.
    this.lightmap = new THREE.Mesh(
        new THREE.PlaneGeometry(1, 1),
        new THREE.MeshBasicMaterial({ map: new THREE.VideoTexture(video), blending: THREE.AdditiveBlending,
                                      depthWrite: false, toneMapped: false }));
    this.lightmap.renderOrder = 1;
    this.lightmap.material.map.colorSpace = THREE.SRGBColorSpace;
    this.world.add(this.screenBox, this.lightmap);
    this.video = video;
    this.receivers = [];  // { box, lightmap } of each receiver besides the screen

    this.proxy = new THREE.Mesh(new THREE.BoxGeometry(proxy.outline[0], proxy.outline[1], proxy.thickness),
                                glassMaterial(quality, 1.5, proxy.thickness));
    this.proxy.renderOrder = 2;
    // The server turns the object about its own origin (object.position), not
    // about the slab's middle: the slab hangs in a frame at that origin, at
    // its offset in object coordinates (undoing the pose the proxy came with).
    this.drawnPose = new THREE.Object3D();
    this.drawnPose.rotation.order = 'XYZ';
    this.drawnPose.add(this.proxy);
    const turned = new THREE.Euler(...proxy.rotation_deg.map(THREE.MathUtils.degToRad), 'XYZ');
    this.proxy.position.copy(vec(proxy.center).sub(vec(proxy.position))
      .applyQuaternion(new THREE.Quaternion().setFromEuler(turned).invert()));
    // The gizmos move `handle` (the object's origin and rotation); the drawn
    // slab follows it, or in synchronous mode the pose of the frame on screen.
    this.handle = new THREE.Object3D();
    this.handle.rotation.order = 'XYZ';
    this.world.add(this.drawnPose, this.handle);

    this.sun = new THREE.DirectionalLight(0xffffff, 0.8);
    this.lightMarker = new THREE.Mesh(new THREE.SphereGeometry(3, 16, 12),
                                      new THREE.MeshBasicMaterial({ color: 0xffee88 }));
    this.lightArrow = new THREE.ArrowHelper(new THREE.Vector3(0, 0, -1), new THREE.Vector3(), 40, 0xffee88);
    this.world.add(this.sun, this.sun.target, this.lightMarker, this.lightArrow);
    this.resize();
    window.addEventListener('resize', () => this.resize());
  }

  resize() {
    const { clientWidth: w, clientHeight: h } = this.renderer.domElement.parentElement;
    this.renderer.setSize(w, h);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
  }

  // Places screen, receivers, lightmaps, light and the requested object
  // pose from the session's parameters (scene format keys) and the atlas
  // the server renders them into.
  apply(params, atlas) {
    this.placeSurfaces(params, atlas);
    const s = params.screen;
    // A directional light has no position: its marker hangs this far from
    // the object, close enough to be framed with it and grabbed.
    const object = vec(params.object.position);
    const size = Math.max(s.width, s.height, this.proxy.geometry.parameters.width, this.proxy.geometry.parameters.height);
    if (this.lightDistance === undefined) this.lightDistance = 0.9 * size;
    this.lightMarker.scale.setScalar(size / 120);
    const o = params.object;
    if (this.proxy.material.ior !== undefined) this.proxy.material.ior = o.ior;
    this.handle.position.copy(vec(o.position));
    this.handle.rotation.set(...o.rotation_deg.map(THREE.MathUtils.degToRad), 'XYZ');
    this.placeLight(params.light);
    if (!this.framed) {
      this.framed = true;
      this.frame(params);
    }
  }

  // The screen rectangle the server renders (it may follow the light):
  // the lightmap lies just in front of it, covering exactly that rectangle.
  placeScreen(s) {
    if (s) placeRectangle(this.lightmap, this.screenBox, s, 1.15);
  }

  // The picture is an atlas when the scene has receivers (a floor, walls):
  // each surface's irradiance in its own tile, in the order screen,
  // receivers. Every surface gets a board and a lightmap showing its tile.
  placeSurfaces(params, atlas) {
    this.placeScreen(params.screen);
    const receivers = params.receivers || [];
    const { width, height } = params.render;
    const tiles = atlas && atlas.length === receivers.length + 1 ? atlas : [{ x: 0, y: 0, width, height }];
    showTile(this.lightmap.material.map, tiles[0], width, height);
    // A receiver whose shape changed (a rectangle, a lathe of other points, a mesh) is made anew.
    const kind = shapeKey;
    const keep = this.receivers.findIndex((have, i) => i >= receivers.length || have.kind !== kind(receivers[i]));
    while (keep >= 0 && this.receivers.length > keep) {
      const gone = this.receivers.pop();
      this.world.remove(gone.box, gone.lightmap);
      gone.lightmap.material.map.dispose();
      if (gone.kind !== 'rectangle') gone.box.geometry.dispose();
    }
    while (this.receivers.length < receivers.length) {
      const r = receivers[this.receivers.length];
      const shape = shapeGeometry(r, this.shapes);
      const box = shape ? new THREE.Mesh(shape, new THREE.MeshStandardMaterial({
        color: 0x8a8478, roughness: 0.7, side: THREE.DoubleSide })) : new THREE.Mesh(this.screenBox.geometry, this.screenBox.material);
      box.receiveShadow = true;
      box.castShadow = !!shape;
      const map = new THREE.VideoTexture(this.video);
      map.colorSpace = THREE.SRGBColorSpace;
      // On a shape the light lies on its body: drawn over it, pulled toward the eye.
      const lightmap = new THREE.Mesh(shape || this.lightmap.geometry, new THREE.MeshBasicMaterial({
        map, blending: THREE.AdditiveBlending, depthWrite: false, toneMapped: false, side: THREE.DoubleSide,
        polygonOffset: !!shape, polygonOffsetFactor: -1, polygonOffsetUnits: -4 }));
      lightmap.renderOrder = 1;
      this.world.add(box, lightmap);
      this.receivers.push({ box, lightmap, kind: kind(r) });
    }
    receivers.forEach((r, i) => {
      const { box, lightmap } = this.receivers[i];
      const shaped = box.geometry !== this.screenBox.geometry;
      if (shaped) placeShape([lightmap, box], r);
      else if (r.width) placeRectangle(lightmap, box, r, 1.0);
      box.visible = lightmap.visible = shaped || !r.mesh;  // a mesh the scene did not bring: not drawn
      showTile(lightmap.material.map, tiles[i + 1] || tiles[0], width, height);
    });
  }

  // The first view: from the object's side of the screen (of all the
  // surfaces, with receivers), 10 degrees off its normal, close enough that
  // the screen (where the caustic is) fills as much of the view as it can
  // while the object and the light's marker stay in it. Fitting is exact for a perspective camera: a point at
  // (x, y) across and z towards the camera from the target is inside when
  // the distance is at least z + |x| / tan(half width angle), likewise y.
  frame(params) {
    this.world.updateMatrixWorld(true);
    const toScene = (p) => p.clone().applyMatrix4(this.world.matrixWorld);
    // Every surface that shows light: the screen, and receivers (a floor,
    // a wall), seen from the side their areas face on the whole.
    const surfaces = [params.screen, ...(params.receivers || [])];
    const normal = new THREE.Vector3(), centre = new THREE.Vector3();
    let area = 0;
    for (const s of surfaces) {
      const weight = surfaceArea(s, this.shapes);
      // A lathe faces every way round its axis: it weighs in where, not which way.
      if (!s.lathe) normal.addScaledVector(toScene(vec(s.normal)).sub(toScene(new THREE.Vector3())), weight);
      centre.addScaledVector(toScene(vec(s.center)), weight);
      area += weight;
    }
    // Surfaces that face each other cancel: then the screen's side.
    if (normal.length() < 1e-6 * area) normal.copy(toScene(vec(params.screen.normal)).sub(toScene(new THREE.Vector3())));
    normal.normalize();
    centre.divideScalar(area);
    const points = [];
    for (const board of [this.screenBox, ...this.receivers.map((r) => r.box)]) {
      const corners = new THREE.Box3().setFromObject(board);
      for (let i = 0; i < 8; ++i)
        points.push(new THREE.Vector3(i & 1 ? corners.max.x : corners.min.x, i & 2 ? corners.max.y : corners.min.y,
                                      i & 4 ? corners.max.z : corners.min.z));
    }
    this.proxy.updateMatrixWorld(true);
    const slab = new THREE.Box3().setFromObject(this.proxy);
    points.push(slab.min, slab.max, this.lightMarker.getWorldPosition(new THREE.Vector3()));
    // Looking down at the screen from its front, turned a little sideways.
    const side = Math.abs(normal.y) < 0.9 ? new THREE.Vector3(0, 1, 0) : new THREE.Vector3(1, 0, 0);
    const across = new THREE.Vector3().crossVectors(normal, side).normalize();
    // A pool's floor is seen through its water, obliquely enough that the
    // surface reads as one.
    const tilt = THREE.MathUtils.degToRad(params.water ? 40 : 10), turn = THREE.MathUtils.degToRad(30);
    const toward = normal.clone().multiplyScalar(Math.cos(tilt))
      .addScaledVector(across.applyAxisAngle(normal, turn), Math.sin(tilt)).normalize();
    // Aimed between the screen and the middle of everything, nearer the screen.
    const middle = new THREE.Box3().setFromPoints(points).getCenter(new THREE.Vector3());
    const target = centre.clone().lerp(middle, 0.35);
    this.camera.position.copy(target).add(toward);
    this.camera.lookAt(target);
    this.camera.updateMatrixWorld(true);
    const right = new THREE.Vector3().setFromMatrixColumn(this.camera.matrixWorld, 0);
    const up = new THREE.Vector3().setFromMatrixColumn(this.camera.matrixWorld, 1);
    const tanY = Math.tan(THREE.MathUtils.degToRad(this.camera.fov / 2)) * 0.92;  // a margin
    const tanX = tanY * this.camera.aspect;
    // The HUD (top) and the mode toolbar (bottom) cover some of the page.
    const height = this.renderer.domElement.clientHeight || 1;
    const tanTop = tanY * (1 - 2 * 48 / height), tanBottom = tanY * (1 - 2 * 72 / height);
    let distance = 0;
    for (const p of points) {
      const d = p.clone().sub(target);
      const y = d.dot(up);
      distance = Math.max(distance, d.dot(toward) + Math.abs(d.dot(right)) / tanX,
                          d.dot(toward) + Math.abs(y) / (y > 0 ? tanTop : tanBottom));
    }
    this.camera.position.copy(target).addScaledVector(toward, distance);
    this.camera.lookAt(target);
    // A pool 2 m across is framed from a few metres: a near plane 1 away
    // would cut into it as the camera zooms in. The classic scenes, framed
    // from 80 or more, keep 1.
    this.camera.near = Math.min(1, distance / 50);
    this.camera.updateProjectionMatrix();
    this.target = target;
    furnish(this, new THREE.Box3().setFromPoints(points));
  }

  /// Swaps the glass and the shadows for the cheaper path, or back.
  setQuality(quality) {
    if (quality === this.quality) return;
    this.quality = quality;
    const ior = this.proxy.material.ior ?? 1.5;
    this.proxy.material.dispose();
    this.proxy.material = glassMaterial(quality, ior, this.proxy.geometry.parameters.depth);
    setRoomQuality(this, quality);
    this.renderer.setPixelRatio(pixelRatio(quality));
    this.resize();
    // Shadow maps on or off: every lit material compiles anew.
    this.scene.traverse((o) => { if (o.material) o.material.needsUpdate = true; });
  }

  // Where the light (or, for a directional one, its marker) is.
  lightPosition(light, target) {
    if (light.type === 'point') return vec(light.position);
    return target.clone().addScaledVector(vec(light.direction).normalize(), -this.lightDistance);
  }

  placeLight(light) {
    const target = this.handle.position;
    const position = this.lightPosition(light, target);
    this.lightMarker.position.copy(position);
    this.lightArrow.position.copy(position);
    this.lightArrow.setDirection(target.clone().sub(position).normalize());
    this.lightArrow.setLength(0.6 * Math.max(1e-3, position.distanceTo(target)));
    this.sun.position.copy(position);
    this.sun.target.position.copy(target);
  }

  // Scene-format values for what the gizmos changed.
  objectPose() {
    const r = this.handle.rotation;
    return { position: this.handle.position.toArray(), rotation_deg: [r.x, r.y, r.z].map(THREE.MathUtils.radToDeg) };
  }

  lightFromMarker(type) {
    const position = this.lightMarker.position;
    if (type === 'point') return { position: position.toArray() };
    const direction = this.handle.position.clone().sub(position).normalize();
    return { direction: direction.toArray() };
  }

  showPose(pose) {
    if (!pose) return;
    this.drawnPose.position.copy(vec(pose.position));
    this.drawnPose.rotation.set(...pose.rotation_deg.map(THREE.MathUtils.degToRad), 'XYZ');
  }

  followHandle() {
    this.drawnPose.position.copy(this.handle.position);
    this.drawnPose.rotation.copy(this.handle.rotation);
  }

  render() { this.renderer.render(this.scene, this.camera); }
}
