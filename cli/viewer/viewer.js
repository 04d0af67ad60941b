// pleat viewer: plays the flipbook glb that `pleat shade` writes and relights it live from the cones it
// carries per vertex and side (_SKY_VISIBILITY: A; _BENT_CONE: unit bent normal, cosine of the half-angle of
// the circular cone with the cone's solid angle). Radiance per vertex and side, as pleat shade computes it
// (Stewart-Langer inter-reflection, docs/method.md section 10):
//   E / pi = L_sky A + E_sun max(0, n . s) / pi   (the sun counts when s lies inside the bent cone)
//   B = rho (E / pi) / (1 - rho (1 - A)),  then exposure, Reinhard on luminance (white 4) and sRGB.
// The sky term equals pleat shade's `--light sky:L` exactly; the sun term is an approximation (pleat tests the
// sun against the cone's pieces, the viewer against the bent cone). Colours are computed on the CPU for the
// shown frame whenever a control moves. URL parameters set the controls (frame, sky, sun, az, el, albedo,
// exposure, baked=1); dump=1 writes the shown frame's sRGB colours into <pre id="dump"> (for tests). Drag
// with the mouse to orbit; hold Shift and move the pointer to drag the sun across the sky.
/* global THREE, PLEAT_GLB */
(function () {
  "use strict";
  const query = new URLSearchParams(window.location.search);
  const status = document.getElementById("status");
  const controls = ["frame", "sky", "sun", "az", "el", "albedo", "exposure"];
  const input = {};
  for (const name of controls) {
    input[name] = document.getElementById(name);
    if (query.has(name)) input[name].value = query.get(name);
  }
  const baked = document.getElementById("baked");
  baked.checked = query.get("baked") === "1";

  // ---- Scene ----
  const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  renderer.setSize(window.innerWidth, window.innerHeight);
  renderer.setClearColor(0x202428);
  document.body.appendChild(renderer.domElement);
  const scene = new THREE.Scene();
  const camera = new THREE.PerspectiveCamera(35, window.innerWidth / window.innerHeight, 0.01, 1000);
  const orbit = new THREE.OrbitControls(camera, renderer.domElement);
  orbit.addEventListener("change", draw);
  window.addEventListener("resize", function () {
    camera.aspect = window.innerWidth / window.innerHeight;
    camera.updateProjectionMatrix();
    renderer.setSize(window.innerWidth, window.innerHeight);
    draw();
  });

  let frames = [];  // per frame: { node, sides: [front, back] } with side = { mesh, baked, live, ... }

  function draw() {
    renderer.render(scene, camera);
  }

  function linearToSrgb(c) {
    if (!(c > 0)) return 0;
    if (c >= 1) return 1;
    return c <= 0.0031308 ? 12.92 * c : 1.055 * Math.pow(c, 1 / 2.4) - 0.055;
  }

  /// pleat's tone mapping (shading/shade.cpp tone_map): exposure, Reinhard on luminance, sRGB.
  function toneMap(r, g, b, exposure, out, k) {
    r = Math.max(r, 0) * exposure;
    g = Math.max(g, 0) * exposure;
    b = Math.max(b, 0) * exposure;
    const y = 0.2126 * r + 0.7152 * g + 0.0722 * b;
    if (y > 0) {
      const mapped = (y * (1 + y / 16)) / (1 + y);
      r *= mapped / y;
      g *= mapped / y;
      b *= mapped / y;
    }
    out[k] = linearToSrgb(Math.fround(r));
    out[k + 1] = linearToSrgb(Math.fround(g));
    out[k + 2] = linearToSrgb(Math.fround(b));
  }

  function sunDirection() {
    const az = (Number(input.az.value) * Math.PI) / 180, el = (Number(input.el.value) * Math.PI) / 180;
    return [Math.cos(el) * Math.sin(az), Math.sin(el), Math.cos(el) * Math.cos(az)];  // towards the sun, y up
  }

  function relight(side) {
    const colour = side.mesh.geometry.attributes.color;
    const out = colour.array;
    if (baked.checked) {
      for (let k = 0; k < out.length; ++k) out[k] = linearToSrgb(side.baked[k]);
    } else {
      const sky = Number(input.sky.value), sun = Number(input.sun.value), rho = Number(input.albedo.value);
      const exposure = Number(input.exposure.value);
      const s = sunDirection();
      const a = side.a, cone = side.cone, n = side.mesh.geometry.attributes.normal.array;
      for (let i = 0; i < a.length; ++i) {
        let e = sky * a[i];
        if (sun > 0) {
          const inside = cone[4 * i] * s[0] + cone[4 * i + 1] * s[1] + cone[4 * i + 2] * s[2] >= cone[4 * i + 3];
          const cosine = n[3 * i] * s[0] + n[3 * i + 1] * s[1] + n[3 * i + 2] * s[2];
          if (inside && cosine > 0) e += (sun * cosine) / Math.PI;
        }
        const radiance = (rho * e) / (1 - rho * (1 - a[i]));
        toneMap(radiance, radiance, radiance, exposure, out, 3 * i);
      }
    }
    colour.needsUpdate = true;
  }

  function show() {
    const f = Number(input.frame.value);
    frames.forEach(function (frame, j) {
      frame.node.visible = j === f;
    });
    for (const side of frames[f].sides) relight(side);
    for (const name of controls) {
      const value = Number(input[name].value);
      document.getElementById(name + "_v").textContent = name === "frame" ? String(value) : value.toFixed(2);
    }
    draw();
    if (query.get("dump") === "1") {
      const sides = frames[f].sides.map(function (side) {
        return Array.from(side.mesh.geometry.attributes.color.array);
      });
      document.getElementById("dump").textContent = JSON.stringify({ frame: f, front: sides[0], back: sides[1] });
    }
  }

  function load(gltf) {
    const root = gltf.scene.children[0];
    for (const node of root.children) {
      const meshes = node.isMesh ? [node] : node.children.filter(function (c) { return c.isMesh; });
      const sides = meshes.map(function (mesh) {
        const g = mesh.geometry;
        if (!g.attributes._sky_visibility || !g.attributes._bent_cone)
          throw new Error("this glb carries no cones (_SKY_VISIBILITY, _BENT_CONE): write it with pleat shade");
        g.computeVertexNormals();
        const side = {
          mesh: mesh,
          baked: g.attributes.color.array.slice(),
          a: g.attributes._sky_visibility.array,
          cone: g.attributes._bent_cone.array,
        };
        mesh.material = new THREE.MeshBasicMaterial({ vertexColors: THREE.VertexColors, side: THREE.FrontSide });
        return side;
      });
      node.scale.set(1, 1, 1);  // the flipbook's scale animation is replaced by `visible`
      frames.push({ node: node, sides: sides });
    }
    scene.add(gltf.scene);
    // Frame the whole sequence from a three-quarter view.
    const box = new THREE.Box3().setFromObject(gltf.scene);
    const centre = box.getCenter(new THREE.Vector3()), size = box.getSize(new THREE.Vector3()).length();
    camera.position.copy(centre).add(new THREE.Vector3(0.55, 0.45, 0.7).multiplyScalar(1.5 * size));
    camera.near = size / 100;
    camera.far = size * 10;
    camera.updateProjectionMatrix();
    orbit.target.copy(centre);
    orbit.update();
    input.frame.max = String(frames.length - 1);
    input.frame.value = String(Math.min(Number(query.get("frame") || 0), frames.length - 1));
    for (const name of controls) input[name].addEventListener("input", show);
    // Drag the sun: with Shift held, the pointer's position over the view sets its azimuth and elevation.
    renderer.domElement.addEventListener("pointermove", function (event) {
      if (!event.shiftKey) return;
      input.az.value = String(Math.round(360 * (event.clientX / window.innerWidth) - 180));
      input.el.value = String(Math.round(90 - 180 * (event.clientY / window.innerHeight)));
      if (Number(input.sun.value) === 0) input.sun.value = "3";
      show();
    });
    orbit.enabled = true;
    window.addEventListener("keydown", function (event) {
      if (event.key === "Shift") orbit.enabled = false;  // Shift + move drags the sun, not the camera
    });
    window.addEventListener("keyup", function (event) {
      if (event.key === "Shift") orbit.enabled = true;
    });
    baked.addEventListener("change", show);
    let timer = null;
    document.getElementById("play").addEventListener("click", function () {
      if (timer) {
        clearInterval(timer);
        timer = null;
        return;
      }
      timer = setInterval(function () {
        input.frame.value = String((Number(input.frame.value) + 1) % frames.length);
        show();
      }, 1000 / 24);
    });
    status.textContent = frames.length + " frames, " + frames[0].sides[0].a.length + " vertices";
    show();
    document.title = "pleat viewer — ready";
  }

  try {
    const text = atob(PLEAT_GLB);
    const bytes = new Uint8Array(text.length);
    for (let i = 0; i < text.length; ++i) bytes[i] = text.charCodeAt(i);
    new THREE.GLTFLoader().parse(bytes.buffer, "", load, function (error) {
      status.textContent = "cannot read the glb: " + error;
    });
  } catch (error) {
    status.textContent = "cannot read the glb: " + error.message;
  }
})();
