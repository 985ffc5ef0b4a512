// The room the viewer draws around the streamed caustic: floor, screen, the
// light, a plain slab standing in for the object (never the real mesh), and
// the lightmap plane that carries the video with additive blending.
// Everything sits in a group whose local axes are the server's world axes
// (z along the light's fall); the group turns that z into three.js's y-up.
import * as THREE from 'three';

const vec = (a) => new THREE.Vector3(a[0], a[1], a[2]);

export class CausticRoom {
  constructor(container, video, proxy) {
    this.renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(Math.min(window.devicePixelRatio, 2));
    container.append(this.renderer.domElement);
    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(0x181c20);
    this.camera = new THREE.PerspectiveCamera(45, 1, 1, 5000);
    this.camera.position.set(160, 140, 200);
    this.world = new THREE.Group();
    this.world.rotation.x = -Math.PI / 2;
    this.world.updateMatrixWorld();
    this.scene.add(this.world);
    this.scene.add(new THREE.HemisphereLight(0xcfd8e0, 0x202428, 0.6));

    this.screenBox = new THREE.Mesh(new THREE.BoxGeometry(1, 1, 1),
                                    new THREE.MeshStandardMaterial({ color: 0x40454a, roughness: 0.9 }));
    this.lightmap = new THREE.Mesh(
        new THREE.PlaneGeometry(1, 1),
        new THREE.MeshBasicMaterial({ map: new THREE.VideoTexture(video), blending: THREE.AdditiveBlending,
                                      transparent: true, depthWrite: false, toneMapped: false }));
    this.lightmap.material.map.colorSpace = THREE.SRGBColorSpace;
    this.world.add(this.screenBox, this.lightmap);

    const glass = new THREE.MeshPhysicalMaterial({ color: 0xddeeff, transmission: 0.9, roughness: 0.05,
                                                   thickness: 2, transparent: true, opacity: 0.6 });
    this.proxy = new THREE.Mesh(new THREE.BoxGeometry(proxy.outline[0], proxy.outline[1], proxy.thickness), glass);
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

    this.sun = new THREE.DirectionalLight(0xffffff, 1.2);
    this.lightMarker = new THREE.Mesh(new THREE.SphereGeometry(3, 16, 12),
                                      new THREE.MeshBasicMaterial({ color: 0xffee88 }));
    this.lightArrow = new THREE.ArrowHelper(new THREE.Vector3(0, 0, -1), new THREE.Vector3(), 40, 0xffee88);
    this.world.add(this.sun, this.sun.target, this.lightMarker, this.lightArrow);
    const floor = new THREE.Mesh(new THREE.PlaneGeometry(2000, 2000),
                                 new THREE.MeshStandardMaterial({ color: 0x2a2f34, roughness: 1 }));
    floor.position.y = -400;
    floor.rotation.x = -Math.PI / 2;
    this.scene.add(floor);
    this.resize();
    window.addEventListener('resize', () => this.resize());
  }

  resize() {
    const { clientWidth: w, clientHeight: h } = this.renderer.domElement.parentElement;
    this.renderer.setSize(w, h);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
  }

  // Places screen, lightmap, light and the requested object pose from the
  // session's parameters (scene format keys).
  apply(params) {
    const s = params.screen;
    const normal = vec(s.normal).normalize();
    const up = vec(s.up).normalize();
    const right = new THREE.Vector3().crossVectors(up, normal).normalize();
    const basis = new THREE.Matrix4().makeBasis(right, up, normal);
    // Just in front of the screen, covering exactly the rendered rectangle.
    this.lightmap.position.copy(vec(s.center)).addScaledVector(normal, 0.05);
    this.lightmap.quaternion.setFromRotationMatrix(basis);
    this.lightmap.scale.set(s.width, s.height, 1);
    this.screenBox.position.copy(vec(s.center)).addScaledVector(normal, -1);
    this.screenBox.quaternion.copy(this.lightmap.quaternion);
    this.screenBox.scale.set(s.width * 1.15, s.height * 1.15, 2);

    // A directional light has no position: its marker hangs this far from
    // the object, close enough to be framed with it and grabbed.
    const object = vec(params.object.position);
    const reach = Math.max(s.width, s.height, object.distanceTo(vec(s.center)));
    this.lightDistance = 0.75 * reach;
    this.lightMarker.scale.setScalar(reach / 40);
    if (!this.framed) {
      // Look at object, screen and light from a distance that fits them all.
      this.framed = true;
      const box = new THREE.Box3().setFromPoints([object, vec(s.center), this.lightPosition(params.light, object)]);
      const sphere = box.getBoundingSphere(new THREE.Sphere());
      const radius = Math.hypot(sphere.radius, 0.5 * Math.max(s.width, s.height));
      const target = sphere.center.clone().applyMatrix4(this.world.matrixWorld);
      const distance = (1.1 * radius) / Math.tan(THREE.MathUtils.degToRad(this.camera.fov / 2));
      this.camera.position.copy(target).addScaledVector(new THREE.Vector3(0.9, 0.6, 1.2).normalize(), distance);
      this.camera.lookAt(target);
      this.target = target;
    }
    const o = params.object;
    this.handle.position.copy(vec(o.position));
    this.handle.rotation.set(...o.rotation_deg.map(THREE.MathUtils.degToRad), 'XYZ');
    this.placeLight(params.light);
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

  // Where the slab's middle is drawn, in scene coordinates.
  drawnCentre() {
    return this.world.worldToLocal(this.proxy.getWorldPosition(new THREE.Vector3())).toArray();
  }

  // Where an object of the room is drawn on the page, in CSS pixels.
  pagePoint(object) {
    const p = object.getWorldPosition(new THREE.Vector3()).project(this.camera);
    const r = this.renderer.domElement.getBoundingClientRect();
    return [r.left + ((p.x + 1) / 2) * r.width, r.top + ((1 - p.y) / 2) * r.height];
  }

  render() { this.renderer.render(this.scene, this.camera); }
}
