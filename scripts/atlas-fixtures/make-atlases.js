// Packs PNG sprites into atlases with free-tex-packer-core, in the forms
// depthcull reads: TexturePacker JSON hash and array, Phaser 3 (the
// "textures" multipack form) and cocos2d plist, with rotation and trimming.
//
//   node make-atlases.js OUT_DIR MAX_PAGE_SIDE SPRITE.png...
//
// A small MAX_PAGE_SIDE makes several pages (a multipack). Deterministic
// for the same inputs and package version.
const fs = require("fs");
const path = require("path");
const { packAsync } = require("free-tex-packer-core");

const [outDir, side, ...sprites] = process.argv.slice(2);
if (!outDir || !side || sprites.length === 0) {
  console.error("usage: node make-atlases.js OUT_DIR MAX_PAGE_SIDE SPRITE.png...");
  process.exit(2);
}
fs.mkdirSync(outDir, { recursive: true });
// Sprites larger than a page cannot be packed: left out, said so.
const images = [];
for (const p of sprites) {
  const contents = fs.readFileSync(p);
  const w = contents.readUInt32BE(16), h = contents.readUInt32BE(20);
  if (Math.max(w, h) + 2 > Number(side)) console.log("skipped " + path.basename(p) + " (" + w + "x" + h + ": larger than a page)");
  else images.push({ path: path.basename(p), contents });
}
const forms = [
  ["hash", "JsonHash"],
  ["array", "JsonArray"],
  ["phaser3", "Phaser3"],
  ["cocos2d", "Cocos2d"],
];
(async () => {
  for (const [name, exporter] of forms) {
    const files = await packAsync(images, {
      textureName: name,
      width: Number(side),
      height: Number(side),
      padding: 1,
      allowRotation: true,
      allowTrim: true,
      detectIdentical: true,
      exporter,
      packer: "MaxRectsBin",
      packerMethod: "BestShortSideFit",
      removeFileExtension: false,
      prependFolderName: false,
      appInfo: { url: "https://www.npmjs.com/package/free-tex-packer-core", version: "free-tex-packer-core" },
    });
    for (const f of files) fs.writeFileSync(path.join(outDir, f.name), f.buffer);
    console.log(exporter + ": " + files.map((f) => f.name).join(" "));
    if (name === "phaser3") {
      // The packer writes one JSON per page; TexturePacker's Phaser 3
      // multipack is one JSON listing every page in "textures": merge.
      const pages = files.filter((f) => f.name.endsWith(".json")).sort((a, b) => a.name.localeCompare(b.name));
      const merged = JSON.parse(pages[0].buffer.toString());
      for (const f of pages.slice(1)) merged.textures.push(...JSON.parse(f.buffer.toString()).textures);
      fs.writeFileSync(path.join(outDir, "phaser3-multi.json"), JSON.stringify(merged, null, "\t") + "\n");
      console.log("Phaser3 multipack: phaser3-multi.json (" + merged.textures.length + " textures)");
    }
  }
})().catch((e) => {
  console.error(e);
  process.exit(1);
});
