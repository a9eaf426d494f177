"use strict";
window.addEventListener("error", function (e) {
  document.body.dataset.errors = (document.body.dataset.errors || "") + e.message + ";";
});
function sortBy(th) {
  const table = th.closest("table"), body = table.tBodies[0];
  const col = Array.prototype.indexOf.call(th.parentNode.children, th);
  const asc = !th.classList.contains("asc");
  table.querySelectorAll("th").forEach(function (h) { h.classList.remove("asc", "desc"); });
  th.classList.add(asc ? "asc" : "desc");
  const key = function (row) {
    const cell = row.children[col];
    if (th.dataset.sort === "num") {
      const v = parseFloat(cell.dataset.v);
      return isNaN(v) ? Infinity : v;
    }
    return cell.textContent;
  };
  const rows = Array.from(body.rows);
  rows.sort(function (a, b) {
    const x = key(a), y = key(b);
    const c = x < y ? -1 : x > y ? 1 : 0;
    return asc ? c : -c;
  });
  rows.forEach(function (r) { body.appendChild(r); });
}
document.querySelectorAll("th[data-sort]").forEach(function (th) {
  th.addEventListener("click", function () { sortBy(th); });
});
function show(section, i) {
  const img = section.querySelector("img");
  const srcs = img.dataset.srcs.split("|"), names = img.dataset.names.split("|");
  img.src = srcs[i];
  img.alt = names[i];
  section.dataset.shown = String(i);
  section.querySelector("input[type=range]").value = String(i);
  section.querySelector(".which").textContent = names[i];
  section.querySelectorAll("button").forEach(function (b) {
    b.classList.toggle("on", b.dataset.i === String(i));
  });
  section.querySelector(".legend").style.visibility = i === 2 ? "visible" : "hidden";
}
function zoom(section, x, y) {
  const frame = section.querySelector(".frame"), img = frame.querySelector("img");
  const w = parseInt(img.getAttribute("width"), 10), h = parseInt(img.getAttribute("height"), 10);
  const zoomed = !frame.classList.contains("zoomed");
  frame.classList.toggle("zoomed", zoomed);
  const s = zoomed ? 4 : 1;
  img.style.width = (w * s) + "px";
  img.style.height = (h * s) + "px";
  frame.scrollLeft = zoomed ? x * s - frame.clientWidth / 2 : 0;
  frame.scrollTop = zoomed ? y * s - frame.clientHeight / 2 : 0;
  section.dataset.zoom = String(s);
}
document.querySelectorAll("section.flip").forEach(function (section) {
  show(section, 0);
  section.querySelectorAll("button").forEach(function (b) {
    b.addEventListener("click", function () { show(section, parseInt(b.dataset.i, 10)); });
  });
  section.querySelector("input[type=range]").addEventListener("input", function (e) {
    show(section, parseInt(e.target.value, 10));
  });
  section.querySelector(".frame img").addEventListener("click", function (e) {
    const r = e.target.getBoundingClientRect(), s = parseInt(section.dataset.zoom || "1", 10);
    zoom(section, (e.clientX - r.left) / s, (e.clientY - r.top) / s);
  });
  section.addEventListener("keydown", function (e) {
    if (e.key === "1" || e.key === "2" || e.key === "3") show(section, parseInt(e.key, 10) - 1);
    else if (e.key === " ") { e.preventDefault(); show(section, section.dataset.shown === "0" ? 1 : 0); }
  });
  section.addEventListener("mouseenter", function () { section.focus({ preventScroll: true }); });
});
function step(section, i) {
  const frames = section.dataset.frames.split("|"), method = section.dataset.method;
  const n = frames[i], imgs = section.querySelectorAll(".frames img");
  imgs[0].src = "frames/" + method + "-" + n + ".png";
  imgs[1].src = "frames/reference-" + n + ".png";
  imgs[2].src = "frames/" + method + "-" + n + "-error.png";
  section.querySelector("input[type=range]").value = String(i);
  section.querySelector(".which").textContent = "frame " + parseInt(n, 10) + " (" + (i + 1) + " of " + frames.length + " measured)";
  section.dataset.shown = String(i);
}
document.querySelectorAll("section.seq").forEach(function (section) {
  const slider = section.querySelector("input[type=range]");
  step(section, parseInt(slider.value, 10));
  slider.addEventListener("input", function () { step(section, parseInt(slider.value, 10)); });
  section.addEventListener("keydown", function (e) {
    const i = parseInt(section.dataset.shown, 10), last = parseInt(slider.max, 10);
    if (e.key === "ArrowLeft" && i > 0) step(section, i - 1);
    else if (e.key === "ArrowRight" && i < last) step(section, i + 1);
  });
});
function selftest() {
  const failures = [];
  const table = document.getElementById("metrics");
  const rmse = table.querySelectorAll("th")[4];
  rmse.click();
  const values = Array.from(table.tBodies[0].rows).map(function (r) { return parseFloat(r.children[4].dataset.v); });
  for (let i = 1; i < values.length; i++) if (values[i - 1] > values[i]) failures.push("RMSE not ascending after a click");
  rmse.click();
  const down = Array.from(table.tBodies[0].rows).map(function (r) { return parseFloat(r.children[4].dataset.v); });
  for (let i = 1; i < down.length; i++) if (down[i - 1] < down[i]) failures.push("RMSE not descending after a second click");
  document.querySelectorAll("section.flip").forEach(function (section) {
    const img = section.querySelector("img"), srcs = img.dataset.srcs.split("|");
    section.dispatchEvent(new KeyboardEvent("keydown", { key: "2" }));
    if (img.getAttribute("src") !== srcs[1]) failures.push(section.id + ": key 2 did not show the reference");
    const slider = section.querySelector("input[type=range]");
    slider.value = "2";
    slider.dispatchEvent(new Event("input"));
    if (img.getAttribute("src") !== srcs[2]) failures.push(section.id + ": the slider did not show the error");
    section.dispatchEvent(new KeyboardEvent("keydown", { key: "1" }));
    img.dispatchEvent(new MouseEvent("click", { clientX: img.getBoundingClientRect().left + 5, clientY: img.getBoundingClientRect().top + 5 }));
    if (section.dataset.zoom !== "4" || img.clientWidth !== 4 * parseInt(img.getAttribute("width"), 10)) failures.push(section.id + ": a click did not zoom ×4");
    img.dispatchEvent(new MouseEvent("click", {}));
    if (section.dataset.zoom !== "1") failures.push(section.id + ": a second click did not zoom back");
  });
  const all = [];
  document.querySelectorAll("img[data-srcs]").forEach(function (img) {
    img.dataset.srcs.split("|").forEach(function (s) { if (all.indexOf(s) < 0) all.push(s); });
  });
  document.querySelectorAll("section.seq").forEach(function (section) {
    const frames = section.dataset.frames.split("|");
    section.dispatchEvent(new KeyboardEvent("keydown", { key: "ArrowLeft" }));
    if (frames.length > 1 && section.dataset.shown !== String(frames.length - 2)) failures.push(section.dataset.method + ": the left arrow did not step back");
    const slider = section.querySelector("input[type=range]");
    slider.value = "0";
    slider.dispatchEvent(new Event("input"));
    if (section.querySelector(".frames img").getAttribute("src").indexOf(frames[0]) < 0) failures.push(section.dataset.method + ": the slider did not show the first frame");
    frames.forEach(function (_, i) {
      step(section, i);
      section.querySelectorAll(".frames img").forEach(function (img) {
        const s = img.getAttribute("src");
        if (all.indexOf(s) < 0) all.push(s);
      });
    });
  });
  Promise.all(all.map(function (s) {
    return new Promise(function (done) {
      const probe = new Image();
      probe.onload = function () { done(probe.naturalWidth > 0 ? null : s); };
      probe.onerror = function () { done(s); };
      probe.src = s;
    });
  })).then(function (missing) {
    missing.forEach(function (s) { if (s) failures.push("image " + s + " did not load"); });
    document.body.dataset.selftest = failures.length ? failures.join("; ") : "ok";
  });
}
window.addEventListener("load", function () {
  document.body.dataset.ready = "1";
  if (location.hash === "#selftest") selftest();
});
