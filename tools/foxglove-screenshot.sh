#!/usr/bin/env bash
# docs/img/foxglove-run.png: the run timeline's MCAP file
# (`audit run ... --format mcap`) opened in Lichtblick (the open-source
# Foxglove Studio fork) with docs/foxglove-layout.json, in headless Chromium,
# photographed by playwright-core.
#
#   tools/foxglove-screenshot.sh LICHTBLICK_TREE [build|serve|shoot|all]
#
# LICHTBLICK_TREE is a work tree of github.com/lichtblick-suite/lichtblick
# (checked out by hand; nothing of it is in this repository). Needs Debian's
# chromium (apt-get install -y chromium), Node.js 20 with npm, and the npm
# registry. Steps:
#   build  yarn install and the web target's development build, in the tree,
#          with two changes made there: the packages the registry lacks at
#          the lockfile's versions pinned to ones it has (resolutions), and
#          the type checker (ForkTsCheckerWebpackPlugin) off: the build
#          transpiles only (the tree's type check fails against the older
#          @lichtblick/tsconfig, which does not change what is bundled), with
#          TypeScript 6's deprecation of that tsconfig's moduleResolution
#          silenced.
#   serve  the built app and a folder with the MCAP file and the layout on
#          127.0.0.1:$PORT (serve-handler, which answers range requests).
#   shoot  playwright-core (npm, in $WORK) drives /usr/bin/chromium to
#          ?ds=remote-file&ds.url=<mcap>&layoutUrl=<layout>, waits for the
#          panels to draw, and saves the PNG.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
tree=$(cd "${1:?usage: tools/foxglove-screenshot.sh LICHTBLICK_TREE [build|serve|shoot|all]}" && pwd)
step=${2:-all}
PORT=${PORT:-8766}
WORK=${WORK:-/tmp/foxglove-shot}
OUT=${OUT:-$here/docs/img/foxglove-run.png}
mkdir -p "$WORK"

export YARN_ENABLE_TELEMETRY=0 COREPACK_ENABLE_DOWNLOAD_PROMPT=0 HUSKY=0
export ELECTRON_SKIP_BINARY_DOWNLOAD=1 PLAYWRIGHT_SKIP_BROWSER_DOWNLOAD=1
export PUPPETEER_SKIP_DOWNLOAD=1 CYPRESS_INSTALL_BINARY=0
# yarn (through corepack) and its packages from npm's configured registry.
registry=$(npm config get registry)
export COREPACK_NPM_REGISTRY=${registry%/} YARN_NPM_REGISTRY_SERVER=${registry%/}

build() {
    cd "$tree"
    # Versions the npm registry serves here (the lockfile's newer ones 404).
    node -e '
const fs = require("fs");
const p = JSON.parse(fs.readFileSync("package.json"));
Object.assign(p.resolutions, {
  "@lichtblick/eslint-plugin": "1.0.4",
  "@lichtblick/rosbag2": "1.0.0",
  "@lichtblick/rosbag2-web": "1.0.0",
  "@lichtblick/tsconfig": "1.0.0",
  "flatbuffers_reflection": "0.0.7",
});
fs.writeFileSync("package.json", JSON.stringify(p, null, 2) + "\n");'
    # Transpile only: no type checker in the bundle's build.
    sed -i 's/^\( *\)new ForkTsCheckerWebpackPlugin(/\1false \&\& new ForkTsCheckerWebpackPlugin(/' \
        packages/suite-base/webpack.ts
    grep -q 'false && new ForkTsCheckerWebpackPlugin' packages/suite-base/webpack.ts
    # @lichtblick/tsconfig 1.0.0 says moduleResolution node10, which
    # TypeScript 6 reports as an error in every file unless told.
    grep -q 'ignoreDeprecations' packages/suite-base/webpack.ts ||
        sed -i 's/^\( *\)sourceMap: true,$/&\n\1ignoreDeprecations: "6.0",/' packages/suite-base/webpack.ts
    grep -q 'ignoreDeprecations: "6.0"' packages/suite-base/webpack.ts
    mkdir -p "$WORK/bin" && corepack enable --install-directory "$WORK/bin"
    PATH="$WORK/bin:$PATH" YARN_ENABLE_IMMUTABLE_INSTALLS=false nice -n 15 yarn install
    PATH="$WORK/bin:$PATH" NODE_OPTIONS=--max-old-space-size=8192 nice -n 15 yarn web:build:dev
    test -s web/.webpack/index.html
}

serve() {
    # The file and the layout beside the app, one origin (no CORS).
    mkdir -p "$tree/web/.webpack/audit"
    "${AUDIT_BIN:-$here/target/release/audit}" run "$here/tests/fixtures/run/run.mcap" \
        --frame trailer_axle --format mcap --output "$WORK/run.mcap"
    cp "$WORK/run.mcap" "$tree/web/.webpack/audit/run.mcap"
    cp "$here/docs/foxglove-layout.json" "$tree/web/.webpack/audit/layout.json"
    # The remote-file source reads the MCAP file by HTTP range requests:
    # serve-handler (the tree's own dependency) answers them.
    cd "$tree/web/.webpack"
    NODE_PATH="$tree/node_modules" nohup node -e '
const handler = require("serve-handler");
require("http")
  .createServer((req, res) => handler(req, res, { public: "." }))
  .listen(Number(process.argv[1]), "127.0.0.1");' "$PORT" > "$WORK/serve.log" 2>&1 &
    echo $! > "$WORK/serve.pid"
    sleep 1
    curl -sf -o /dev/null "http://127.0.0.1:$PORT/audit/run.mcap"
}

shoot() {
    if [ ! -d "$WORK/node_modules/playwright-core" ]; then
        (cd "$WORK" && npm init -y > /dev/null && npm install --no-audit --no-fund playwright-core)
    fi
    cat > "$WORK/shoot.cjs" << 'EOF'
const { chromium } = require("playwright-core");
(async () => {
  const [base, out, alerts] = process.argv.slice(2);
  const dir = require("fs").mkdtempSync("/tmp/foxglove-chromium-");
  const ctx = await chromium.launchPersistentContext(dir, {
    executablePath: "/usr/bin/chromium",
    headless: true,
    viewport: { width: 1600, height: 900 },
    args: ["--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
      "--disable-background-networking", "--disable-component-update", "--disable-sync",
      "--use-gl=angle", "--use-angle=swiftshader", "--enable-unsafe-swiftshader"],
  });
  const page = ctx.pages()[0] ?? (await ctx.newPage());
  page.on("console", (m) => { if (m.type() === "error" || m.type() === "warning") console.error("console:", m.text()); });
  const url = `${base}/?ds=remote-file&ds.url=${encodeURIComponent(base + "/audit/run.mcap")}` +
    `&layoutUrl=${encodeURIComponent(base + "/audit/layout.json")}`;
  await page.goto(url, { waitUntil: "load", timeout: 120000 });
  // The panels draw once the file is indexed and the layout applied.
  await page.waitForTimeout(Number(process.env.SETTLE_MS ?? 45000));
  // What the app reports about the file (the Alerts tab), then the left
  // sidebar closed ("[", the app's shortcut) so the panels fill the page.
  await page.getByRole("tab", { name: /Alerts/ }).click();
  await page.waitForTimeout(1000);
  await page.screenshot({ path: alerts });
  await page.keyboard.press("[");
  await page.waitForTimeout(5000);
  await page.screenshot({ path: out });
  await ctx.close();
})().catch((e) => { console.error(e); process.exit(1); });
EOF
    (cd "$WORK" && node shoot.cjs "http://127.0.0.1:$PORT" "$OUT" "$WORK/alerts.png")
    echo "wrote $OUT"
}

case "$step" in
    build) build ;;
    serve) serve ;;
    shoot) shoot ;;
    all) build && serve && shoot ;;
    *) echo "unknown step $step" >&2; exit 2 ;;
esac
