// node render.mjs --table shipped|ours|compact|sheen --out FILE.json [--scenes FILE] [--chromium PATH]
// Serves this folder, three's package and our drop-in on 127.0.0.1 (an ephemeral port),
// loads page.html in headless Chromium (WebGL2 on SwiftShader), renders every scene of
// scenes.json on the float path and on the half-float path, then page_webgpu.html with
// WebGPURenderer (WebGPU on SwiftShader, where Chromium offers an adapter), and writes the
// pixels.
// With --table ours the page's import map sends three's
// examples/jsm/lights/RectAreaLightTexturesLib.js to results/textures/three/ — the one
// import a user changes. With --table compact it goes to the compact drop-in
// (RectAreaLightTexturesLib.compact.js), whose init() rebuilds the textures from the
// compact series of ltc_compact.js. With --table sheen it renders the sheen scenes
// (scene.js's renderAllSheen: the sheen alone) with three's shipped textures, once as
// three is (path "shipped") and once after our RectAreaLightSheen.init() (path "recipe"),
// and no WebGPU path (the recipe patches the WebGL shader chunk). --scenes names the
// scene file (relative to this folder; default scenes.json, the GGX check's; the sheen
// check's own is scenes_sheen.json); the output records it.
import { createServer } from 'node:http';
import { readFile, writeFile } from 'node:fs/promises';
import { extname, join, normalize, dirname } from 'node:path';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';

const here = dirname( fileURLToPath( import.meta.url ) );
const arg = ( name, dflt ) => {

	const k = process.argv.indexOf( `--${name}` );
	return k > 0 ? process.argv[ k + 1 ] : dflt;

};
const table = arg( 'table', 'shipped' );
const out = arg( 'out' );
const exe = arg( 'chromium', '/usr/bin/chromium' );
const scenesFile = arg( 'scenes', 'scenes.json' );
const ours = normalize( join( here, '..', '..', arg( 'results', 'results' ), 'textures', 'three' ) );
if ( ! out || ! [ 'shipped', 'ours', 'compact', 'sheen' ].includes( table ) ) {

	console.error( 'usage: node render.mjs --table shipped|ours|compact|sheen --out FILE.json [--scenes FILE] [--results DIR] [--chromium PATH]' );
	process.exit( 2 );

}

const roots = { '/three/': join( here, 'node_modules', 'three' ), '/ours/': ours, '/': here };
const types = { '.js': 'text/javascript', '.mjs': 'text/javascript', '.html': 'text/html', '.json': 'application/json' };
const server = createServer( async ( req, res ) => {

	const url = decodeURIComponent( new URL( req.url, 'http://localhost' ).pathname );
	const prefix = Object.keys( roots ).find( ( p ) => url.startsWith( p ) );
	const path = normalize( join( roots[ prefix ], url.slice( prefix.length ) ) );
	if ( ! path.startsWith( roots[ prefix ] ) ) {

		res.writeHead( 403 ).end();
		return;

	}

	try {

		let body = await readFile( path );
		if ( url === '/page.html' || url === '/page_webgpu.html' ) {

			const imports = url === '/page.html'
				? { 'three': '/three/build/three.module.js', 'three/addons/': '/three/examples/jsm/' }
				: { 'three': '/three/build/three.webgpu.js', 'three/webgpu': '/three/build/three.webgpu.js', 'three/tsl': '/three/build/three.tsl.js', 'three/addons/': '/three/examples/jsm/' };
			if ( table === 'ours' || table === 'compact' ) {

				// the recipe: three's module sent to ours, by its URL (how three's own
				// RectAreaLightUniformsLib reaches it) and by its bare specifier (how an
				// application importing it for RectAreaLightNode.setLTC names it)
				const lib = table === 'ours' ? '/ours/RectAreaLightTexturesLib.js' : '/ours/RectAreaLightTexturesLib.compact.js';
				imports[ '/three/examples/jsm/lights/RectAreaLightTexturesLib.js' ] = lib;
				imports[ 'three/addons/lights/RectAreaLightTexturesLib.js' ] = lib;

			}
			body = body.toString().replace( '__IMPORTMAP__', JSON.stringify( { imports } ) );

		}

		res.writeHead( 200, { 'content-type': types[ extname( path ) ] || 'application/octet-stream' } ).end( body );

	} catch {

		res.writeHead( 404 ).end();

	}

} );
await new Promise( ( ok ) => server.listen( 0, '127.0.0.1', ok ) );
const base = `http://127.0.0.1:${server.address().port}`;
// WebGL2 through ANGLE on SwiftShader; WebGPU (Dawn) on SwiftShader's Vulkan
const browser = await chromium.launch( { executablePath: exe, args: [ '--use-gl=angle', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--enable-unsafe-webgpu', '--no-sandbox' ] } );
try {

	const config = JSON.parse( await readFile( join( here, scenesFile ), 'utf8' ) );
	const result = { table, engine: 'three.js 0.187.0', scenes: `engines/three/${scenesFile}`, paths: {} };
	const runs = table === 'sheen'
		? [ [ 'shipped', false, 'renderAllSheen' ], [ 'recipe', true, 'renderAllSheen' ] ]
		: [ [ 'float', false, 'renderAll' ], [ 'half', true, 'renderAll' ] ];
	for ( const [ path, flag, entry ] of runs ) {

		// a fresh page per path: the recipe patches three's shader chunks for its page only
		const page = await browser.newPage();
		page.on( 'pageerror', ( e ) => console.error( `page error: ${e.message}` ) );
		await page.goto( `${base}/page.html` );
		await page.waitForFunction( () => window.ready === true, null, { timeout: 60000 } );
		const r = await page.evaluate( ( [ c, h, f ] ) => window[ f ]( c, h ), [ config, flag, entry ] );
		result.adapter = r.renderer;
		result.paths[ path ] = r.scenes;
		await page.close();
		console.error( `three.js ${table} table, ${path} path: ${r.scenes.length} scenes rendered (${r.renderer})` );

	}

	// the sheen's WebGPURenderer paths, as three is and with RectAreaLightSheenNode, each on
	// a fresh page, where this Chromium offers a WebGPU adapter
	for ( const [ path, recipe ] of table === 'sheen' ? [ [ 'webgpu-shipped', false ], [ 'webgpu-recipe', true ] ] : [] ) {

		const page = await browser.newPage();
		page.on( 'pageerror', ( e ) => console.error( `page error: ${e.message}` ) );
		await page.goto( `${base}/page_webgpu.html` );
		await page.waitForFunction( () => window.ready === true, null, { timeout: 60000 } );
		const hasGpu = await page.evaluate( async () => !! ( navigator.gpu && await navigator.gpu.requestAdapter() ) );
		if ( hasGpu ) {

			const r = await page.evaluate( ( [ c, h ] ) => window.renderAllSheenWebGPU( c, h ), [ config, recipe ] );
			result.paths[ path ] = r.scenes;
			result.webgpu_adapter = r.adapter;
			console.error( `three.js sheen, ${path} path: ${r.scenes.length} scenes rendered (${r.adapter})` );

		} else {

			console.error( `three.js sheen: no WebGPU adapter in this Chromium, the ${path} path skipped` );

		}

		await page.close();

	}

	// the WebGPURenderer path, where this Chromium offers a WebGPU adapter (skipped with a
	// line otherwise: the judging then has the two WebGL paths)
	const page = table === 'sheen' ? null : await browser.newPage();
	if ( page ) {

		page.on( 'pageerror', ( e ) => console.error( `page error: ${e.message}` ) );
		await page.goto( `${base}/page_webgpu.html` );
		await page.waitForFunction( () => window.ready === true, null, { timeout: 60000 } );
		const hasGpu = await page.evaluate( async () => !! ( navigator.gpu && await navigator.gpu.requestAdapter() ) );
		if ( hasGpu ) {

			const r = await page.evaluate( ( c ) => window.renderAllWebGPU( c ), config );
			result.paths[ r.path ] = r.scenes;
			result.webgpu_adapter = r.adapter;
			console.error( `three.js ${table} table, ${r.path} path: ${r.scenes.length} scenes rendered (${r.adapter})` );

		} else {

			console.error( `three.js ${table} table: no WebGPU adapter in this Chromium, the WebGPURenderer path skipped` );

		}

		await page.close();

	}

	await writeFile( out, JSON.stringify( result ) );

} finally {

	await browser.close();
	server.close();

}
