// ohrp view's page: the live camera images (view.js calls setupImages with the hello).

// A second WebSocket, open only while the images are shown (the box ticked and the page
// visible): the server asks the producer for images only while some page holds one open.
// Each message: int32 camera, width, height, 0; float64 time, frame; then RGB8 rows.
let imagesWs = null, cameraList = [];
function setupImages(h) {
  cameraList = h.camera_list || [];
  if (!cameraList.length) return;
  $('images_toggle').hidden = false;
  $('images').innerHTML = cameraList.map((c, i) => '<figure><canvas id="camimg' + i + '" width="' + c.width +
      '" height="' + c.height + '"></canvas><figcaption id="camcap' + i + '">' + c.name +
      ': no image yet</figcaption></figure>').join('');
  const box = $('show_images');
  box.checked = params.get('images') === '1';
  box.onchange = updateImages;
  document.addEventListener('visibilitychange', updateImages);
  updateImages();
}

function updateImages() {
  const want = $('show_images').checked && !document.hidden;
  $('images').style.display = want ? 'flex' : 'none';
  if (want && !imagesWs) {
    const ws = new WebSocket('ws://' + location.host + '/ws/images');
    ws.binaryType = 'arraybuffer';
    // each image drawn is answered: the server sends the next (the newest) only then, so
    // images never queue behind a slow page
    ws.onmessage = (e) => {
      try {
        drawImage(e.data);
        $('images_note').textContent = '';
      } finally {  // answered even when drawing failed: the server would wait forever
        if (ws.readyState === WebSocket.OPEN) ws.send('drawn');
      }
    };
    // closed by the server while still wanted (it restarted, or a network hiccup): said on the
    // page, and asked again every second
    ws.onclose = () => {
      if (imagesWs !== ws) return;
      imagesWs = null;
      $('images_note').textContent = 'camera images: connection lost, reconnecting...';
      setTimeout(updateImages, 1000);
    };
    imagesWs = ws;
  } else if (!want && imagesWs) {
    imagesWs.close();
    imagesWs = null;
  }
  if (!want) $('images_note').textContent = '';
}

function drawImage(buf) {
  const head = new DataView(buf, 0, 32);
  const cam = head.getInt32(0, true), w = head.getInt32(4, true), h = head.getInt32(8, true);
  const t = head.getFloat64(16, true), frame = head.getFloat64(24, true);
  const canvas = $('camimg' + cam);
  if (!canvas || buf.byteLength < 32 + 3 * w * h) return;
  if (canvas.width !== w || canvas.height !== h) { canvas.width = w; canvas.height = h; }
  const rgb = new Uint8Array(buf, 32, 3 * w * h), img = new ImageData(w, h), px = img.data;
  for (let i = 0, j = 0; i < w * h; ++i, j += 3) {
    px[4 * i] = rgb[j]; px[4 * i + 1] = rgb[j + 1]; px[4 * i + 2] = rgb[j + 2]; px[4 * i + 3] = 255;
  }
  canvas.getContext('2d').putImageData(img, 0, 0);
  $('camcap' + cam).textContent = cameraList[cam].name + ': frame ' + frame + ', t = ' + t.toFixed(3) + ' s';
  stateEl.dataset.images = Number(stateEl.dataset.images) + 1;
  if (cam === 0) { stateEl.dataset.imageFrame = frame; stateEl.dataset.imageT = t; }
}
