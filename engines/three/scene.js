// Renders every scene of scenes.json with three.js's WebGLRenderer into a FloatType
// render target (no tone mapping, linear output) and reads the pixels back: the radiance
// of each pixel, and a second pass with each pixel's world position. The LTC textures
// are whatever RectAreaLightTexturesLib.js resolves to through the page's import map,
// installed by RectAreaLightUniformsLib.init() as three's own examples do.
import * as THREE from 'three';
import { RectAreaLightUniformsLib } from 'three/addons/lights/RectAreaLightUniformsLib.js';
import { place } from './place.js';

async function render( config, halfPath, material ) {

	const { width, height } = config;
	const canvas = document.createElement( 'canvas' );
	const renderer = new THREE.WebGLRenderer( { canvas, antialias: false } );
	renderer.toneMapping = THREE.NoToneMapping;
	renderer.setPixelRatio( 1 );
	renderer.setSize( width, height, false );
	if ( halfPath ) {

		// a device without OES_texture_float_linear: three binds the LTC_HALF textures
		const has = renderer.extensions.has.bind( renderer.extensions );
		renderer.extensions.has = ( name ) => name === 'OES_texture_float_linear' ? false : has( name );

	}

	RectAreaLightUniformsLib.init();

	const target = new THREE.WebGLRenderTarget( width, height, { type: THREE.FloatType, format: THREE.RGBAFormat, depthBuffer: true } );
	const scene = new THREE.Scene();
	scene.background = null;
	const s = config.plane_half;
	const plane = new THREE.Mesh( new THREE.PlaneGeometry( 2 * s, 2 * s ), material( 0.5 ) );
	scene.add( plane );
	const light = new THREE.RectAreaLight( 0xffffff, 1.0, 1.0, 1.0 );
	scene.add( light );
	const positions = new THREE.ShaderMaterial( {
		vertexShader: 'varying vec3 wp; void main() { vec4 w = modelMatrix * vec4( position, 1.0 ); wp = w.xyz; gl_Position = projectionMatrix * viewMatrix * w; }',
		fragmentShader: 'varying vec3 wp; void main() { gl_FragColor = vec4( wp, 1.0 ); }'
	} );
	const read = () => {

		const buf = new Float32Array( width * height * 4 );
		renderer.readRenderTargetPixels( target, 0, 0, width, height, buf );
		return Array.from( buf );

	};

	const out = [];
	for ( const sc of config.scenes ) {

		const cam = place( THREE, light, sc, s );
		plane.material = material( sc.roughness );
		renderer.setRenderTarget( target );
		renderer.setClearColor( 0x000000, 0 );
		renderer.clear();
		renderer.render( scene, cam );
		const radiance = read();
		plane.material = positions;
		renderer.clear();
		renderer.render( scene, cam );
		const where = read();
		out.push( { name: sc.name, radiance, positions: where } );

	}

	renderer.setRenderTarget( null );
	return { renderer: renderer.getContext().getParameter( renderer.getContext().VERSION ), scenes: out };

}

window.renderAll = ( config, halfPath ) => render( config, halfPath,
	( roughness ) => new THREE.MeshStandardMaterial( { color: 0xffffff, metalness: 1.0, roughness } ) );

window.renderAllSheen = async function ( config, recipe ) {

	if ( recipe ) {

		const { RectAreaLightSheen } = await import( '/ours/RectAreaLightSheen.js' );
		RectAreaLightSheen.init();

	}

	return render( config, false, ( roughness ) => new THREE.MeshPhysicalMaterial( {
		color: 0x000000, metalness: 0.0, roughness: 1.0, specularIntensity: 0.0,
		sheen: 1.0, sheenColor: 0xffffff, sheenRoughness: roughness
	} ) );

};

window.ready = true;
