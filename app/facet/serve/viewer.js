// facet's served viewer page: sends pointer, wheel, key and resize events (jupyter_rfb's
// vocabulary) over a WebSocket and draws each picture the server sends onto the canvas.
// The canvas carries data-frame (the last picture's index), data-lossless ("1" when it
// is the still view's PNG), data-camera (its camera, facet.Camera.describe) and data-state
// (the status line as data: engine, samples drawn, of how many, triangles, error;
// facet.viewing.core.ViewerCore.state), which tests and benchmarks wait on.
(() => {
  'use strict'
  const canvas = document.getElementById('canvas')
  const status = document.getElementById('status')
  const notice = document.getElementById('notice')
  let noticeTimer = null
  const view = document.getElementById('view')
  const token = new URLSearchParams(location.search).get('token') || ''
  const scheme = location.protocol === 'https:' ? 'wss:' : 'ws:'
  const ws = new WebSocket(`${scheme}//${location.host}/ws?token=${encodeURIComponent(token)}`)
  ws.binaryType = 'blob'
  let meta = null
  let open = false
  let drawn = 0 // the index of the picture on the canvas: decoding may finish out of order
  const send = (event) => { if (open) ws.send(JSON.stringify(event)) }
  const modifiers = (ev) => ['Shift', 'Control', 'Alt', 'Meta'].filter((m) => ev.getModifierState(m))
  const BUTTONS = { 0: 1, 1: 3, 2: 2 } // DOM button -> jupyter_rfb's (1 left, 2 right, 3 middle)

  const resize = () => {
    const r = view.getBoundingClientRect()
    send({ type: 'resize', width: r.width, height: r.height, pixel_ratio: window.devicePixelRatio || 1 })
  }

  ws.onopen = () => { open = true; status.textContent = 'connected'; resize(); canvas.focus() }
  ws.onclose = (ev) => {
    open = false
    status.className = 'error'
    status.textContent = 'disconnected from facet' + (ev.reason ? ': ' + ev.reason : '') +
      ' (the server stopped, or the token is wrong: open the URL facet printed)'
  }
  ws.onmessage = async (ev) => {
    if (typeof ev.data === 'string') { meta = JSON.parse(ev.data); return }
    if (!meta) return
    const m = meta
    meta = null
    const bitmap = await createImageBitmap(new Blob([ev.data], { type: m.mime }))
    if (m.index < drawn) { // a newer picture is already shown: this one is stale
      bitmap.close()
      send({ type: 'frame_feedback', index: m.index })
      return
    }
    drawn = m.index
    if (canvas.width !== m.width || canvas.height !== m.height) {
      canvas.width = m.width
      canvas.height = m.height
    }
    canvas.getContext('2d').drawImage(bitmap, 0, 0)
    bitmap.close()
    canvas.dataset.frame = String(m.index)
    canvas.dataset.lossless = m.lossless ? '1' : '0'
    canvas.dataset.camera = JSON.stringify(m.camera)
    canvas.dataset.state = JSON.stringify(m.state)
    status.className = m.status.includes(' - error: ') ? 'error' : ''
    status.textContent = m.status
    if (m.notices && m.notices.length) { // a key's result, the key map, a warning: shown a while
      notice.textContent = m.notices.join('\n')
      clearTimeout(noticeTimer)
      noticeTimer = setTimeout(() => { notice.textContent = '' }, 6000 + 300 * m.notices.join('\n').split('\n').length)
    }
    send({ type: 'frame_feedback', index: m.index })
  }

  new ResizeObserver(resize).observe(view)

  let pressed = false
  canvas.addEventListener('contextmenu', (ev) => ev.preventDefault())
  canvas.addEventListener('pointerdown', (ev) => {
    canvas.focus()
    canvas.setPointerCapture(ev.pointerId)
    pressed = true
    canvas.style.cursor = 'grabbing'
    send({ type: 'pointer_down', x: ev.offsetX, y: ev.offsetY, button: BUTTONS[ev.button] || 1, modifiers: modifiers(ev) })
    ev.preventDefault()
  })
  // Moves are sent at most once per animation frame (the last position wins).
  let pendingMove = null
  canvas.addEventListener('pointermove', (ev) => {
    if (!pressed) return
    const first = pendingMove === null
    pendingMove = { type: 'pointer_move', x: ev.offsetX, y: ev.offsetY, modifiers: modifiers(ev) }
    if (first) requestAnimationFrame(() => { send(pendingMove); pendingMove = null })
  })
  const up = (ev) => {
    if (!pressed) return
    pressed = false
    canvas.style.cursor = 'grab'
    if (pendingMove !== null) { send(pendingMove); pendingMove = null }
    send({ type: 'pointer_up', x: ev.offsetX, y: ev.offsetY, button: BUTTONS[ev.button] || 1, modifiers: modifiers(ev) })
  }
  canvas.addEventListener('pointerup', up)
  canvas.addEventListener('pointercancel', up)
  canvas.addEventListener('wheel', (ev) => {
    ev.preventDefault()
    const scale = [1, 16, 600][ev.deltaMode] // pixels, lines, pages
    send({ type: 'wheel', x: ev.offsetX, y: ev.offsetY, dx: ev.deltaX * scale, dy: ev.deltaY * scale, modifiers: modifiers(ev) })
  }, { passive: false })
  canvas.addEventListener('keydown', (ev) => {
    if (ev.ctrlKey || ev.metaKey || ev.altKey) return // the browser's own shortcuts
    send({ type: 'key_down', key: ev.key, modifiers: modifiers(ev) })
    ev.preventDefault()
  })
})()
