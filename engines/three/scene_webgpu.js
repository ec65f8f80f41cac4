// The same scenes with three.js's WebGPURenderer (WebGPU on SwiftShader's Vulkan): the
// LTC textures are whatever RectAreaLightTexturesLib.js resolves to through the page's
// import map, handed to the renderer by RectAreaLightNode.setLTC(…init()) as three's
// WebGPU examples do. A FloatType render target, no tone mapping, read back as numbers;
// a second pass with each pixel's world position. Reports which textures three bound
// (LTC_FLOAT where the adapter has float32-filterable, else LTC_HALF).
//
// renderAllWebGPU: the GGX check's white metallic MeshStandardNodeMaterial.
// renderAllSheenWebGPU: the sheen alone (MeshPhysicalNodeMaterial, black dielectric base,
// specularIntensity 0, white sheen of sheenRoughness = the scene's roughness); with
// `recipe`, our RectAreaLightSheenNode.init() runs first.
import * as THREE from 'three/webgpu';
import { positionWorld, vec4 } from 'three/tsl';
import { RectAreaLightTexturesLib } from 'three/addons/lights/RectAreaLightTexturesLib.js';
import { place } from './place.js';

async function renderWebGPU( config, material ) {

	const { width, height } = config;
	const renderer = new THREE.WebGPURenderer( { antialias: false } );
	await renderer.init();
	if ( renderer.backend.isWebGPUBackend !== true ) throw new Error( 'WebGPU backend unavailable' );
	THREE.RectAreaLightNode.setLTC( RectAreaLightTexturesLib.init() );
	renderer.toneMapping = THREE.NoToneMapping;
	renderer.setPixelRatio( 1 );
	renderer.setSize( width, height, false );
	const target = new THREE.RenderTarget( width, height, { type: THREE.FloatType, format: THREE.RGBAFormat, depthBuffer: true } );
	const scene = new THREE.Scene();
	const s = config.plane_half;
	const plane = new THREE.Mesh( new THREE.PlaneGeometry( 2 * s, 2 * s ), material( 0.5 ) );
	scene.add( plane );
	const light = new THREE.RectAreaLight( 0xffffff, 1.0, 1.0, 1.0 );
	scene.add( light );
	// the node material's output drops negative values: positions are written offset by
	// +OFFSET and the offset is taken off after the read-back
	const OFFSET = 4.0;
	const positions = new THREE.MeshBasicNodeMaterial();
	positions.colorNode = vec4( positionWorld.add( OFFSET ), 1.0 );
	// rows from the bottom, as the WebGL path's readRenderTargetPixels returns them
	const read = async () => {

		const buf = await renderer.readRenderTargetPixelsAsync( target, 0, 0, width, height );
		const out = new Array( width * height * 4 );
		for ( let y = 0; y < height; y ++ ) {

			for ( let k = 0; k < width * 4; k ++ ) out[ y * width * 4 + k ] = buf[ ( height - 1 - y ) * width * 4 + k ];

		}

		return out;

	};

	const out = [];
	for ( const sc of config.scenes ) {

		const cam = place( THREE, light, sc, s );
		plane.material = material( sc.roughness );
		renderer.setRenderTarget( target );
		renderer.setClearColor( 0x000000, 0 );
		renderer.clear();
		renderer.render( scene, cam );
		const radiance = await read();
		plane.material = positions;
		renderer.clear();
		renderer.render( scene, cam );
		const where = ( await read() ).map( ( v, k ) => ( k % 4 === 3 || v === 0 ? v : v - OFFSET ) );
		out.push( { name: sc.name, radiance, positions: where } );

	}

	renderer.setRenderTarget( null );
	const float = renderer.backend.hasFeature( 'float32-filterable' );
	const adapter = await navigator.gpu.requestAdapter();
	const info = adapter && adapter.info ? adapter.info : {};
	return { path: float ? 'webgpu-float' : 'webgpu-half', adapter: `WebGPU, ${info.vendor || '?'} ${info.architecture || '?'}`, scenes: out };

}

window.renderAllWebGPU = ( config ) => renderWebGPU( config,
	( roughness ) => new THREE.MeshStandardNodeMaterial( { color: 0xffffff, metalness: 1.0, roughness } ) );

window.renderAllSheenWebGPU = async function ( config, recipe ) {

	if ( recipe ) {

		const { RectAreaLightSheenNode } = await import( '/ours/RectAreaLightSheenNode.js' );
		RectAreaLightSheenNode.init();

	}

	return renderWebGPU( config, ( roughness ) => new THREE.MeshPhysicalNodeMaterial( {
		color: 0x000000, metalness: 0.0, roughness: 1.0, specularIntensity: 0.0,
		sheen: 1.0, sheenColor: 0xffffff, sheenRoughness: roughness
	} ) );

};

window.ready = true;
